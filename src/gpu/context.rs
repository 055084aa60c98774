//! The Vulkan instance, the chosen physical device, the logical device and its queue plan.
//!
//! Everything that owns a Vulkan handle keeps an `Arc<DeviceShared>`, so the device and instance
//! outlive every buffer, image and pipeline made from them, and are destroyed last, in order.

use std::ffi::{CStr, CString, c_void};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::pass::queue_stages;
use super::{GpuError, GpuResult, vk_err};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create the GPU context.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Enable the Khronos validation layer (with synchronization validation) and count its errors.
    pub validation: bool,
    /// Device to use: an index into the enumeration order or a case-insensitive part of its name.
    /// `None` reads `VKGI_DEVICE`, and without it picks discrete > integrated > virtual > CPU.
    pub device: Option<String>,
    /// Presenting to windows on this display: enables the surface extensions it needs on the
    /// instance and VK_KHR_swapchain on the device.
    pub display: Option<winit::raw_window_handle::RawDisplayHandle>,
    /// How the per-pixel passes with two forms run (`None`: as [`PixelPasses::for_device`]).
    pub pixel_passes: Option<PixelPasses>,
}

/// How the per-pixel passes that have both forms (direct lighting, the LPV lookup, tone
/// mapping) run on a device. Both forms give the same image up to the rounding of one sum (the
/// tone map's 8-bit image: of one level).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PixelPasses {
    /// Fragment shaders over a full-screen triangle, writing or blending into render targets.
    Fragment,
    /// Compute shaders reading and writing the images as storage images.
    Compute,
}

impl PixelPasses {
    /// The faster form on a device of `device_type`, as measured: on a CPU device (lavapipe) a
    /// render target's write (and its blend) costs a fraction of a compute pass's imageStore
    /// (docs/performance.md, "Writing shaders for lavapipe"); a GPU may run fragments on a
    /// small part of its chip: an NVIDIA H200 lit 1920x1080 in 0.035 ms as a compute pass and in
    /// 1.19 ms as a fragment pass (docs/performance.md, "Item 4").
    pub fn for_device(device_type: vk::PhysicalDeviceType) -> PixelPasses {
        match device_type {
            vk::PhysicalDeviceType::CPU => PixelPasses::Fragment,
            _ => PixelPasses::Compute,
        }
    }
}

/// Validation-layer messages seen so far. Tests assert that `error_count()` stays zero.
#[derive(Default)]
pub struct ValidationLog {
    errors: AtomicU32,
    first_errors: Mutex<Vec<String>>,
}

impl ValidationLog {
    pub fn error_count(&self) -> u32 {
        self.errors.load(Ordering::SeqCst)
    }

    /// The first few error messages, for a test failure message.
    pub fn first_errors(&self) -> Vec<String> {
        self.first_errors
            .lock()
            .map(|m| m.clone())
            .unwrap_or_default()
    }

    fn record_error(&self, message: String) {
        self.errors.fetch_add(1, Ordering::SeqCst);
        if let Ok(mut first) = self.first_errors.lock()
            && first.len() < 8
        {
            first.push(message);
        }
    }
}

/// One queue the renderer submits to.
#[derive(Clone, Copy, Debug)]
pub struct Queue {
    pub raw: vk::Queue,
    pub family: u32,
    pub index: u32,
    /// Bits of a timestamp that are meaningful on this queue's family; 0 = no timestamps.
    pub timestamp_valid_bits: u32,
    /// The pipeline stages its family runs (`pass::queue_stages`), which its barriers may name.
    pub stages: vk::PipelineStageFlags2,
}

impl Queue {
    pub fn same_queue(&self, other: &Queue) -> bool {
        self.family == other.family && self.index == other.index
    }
}

/// Most async compute queues the plan takes (a method's independent parts share them
/// round-robin when it has more parts than queues).
pub const MAX_ASYNC_COMPUTE_QUEUES: u32 = 8;

/// Which queues do what: one graphics queue, and up to [`MAX_ASYNC_COMPUTE_QUEUES`] distinct
/// compute queues that independent work (a GI method's parts) may run on concurrently. Where the
/// device offers no queue beside the graphics queue (lavapipe), there are none and that work
/// goes to the graphics queue.
#[derive(Clone, Debug)]
pub struct QueuePlan {
    pub graphics: Queue,
    pub async_compute: Vec<Queue>,
}

impl QueuePlan {
    /// The queue for independent part `part` (round-robin over the async compute queues, or
    /// the graphics queue when there are none).
    pub fn part_queue(&self, part: usize) -> Queue {
        if self.async_compute.is_empty() {
            self.graphics
        } else {
            self.async_compute[part % self.async_compute.len()]
        }
    }

    /// True when at least two parts can run at the same time (two distinct compute queues).
    pub fn runs_parts_concurrently(&self) -> bool {
        self.async_compute.len() >= 2
    }

    /// All distinct queue families in the plan (resources shared across them use CONCURRENT).
    pub fn families(&self) -> Vec<u32> {
        let mut families = vec![self.graphics.family];
        for q in &self.async_compute {
            if !families.contains(&q.family) {
                families.push(q.family);
            }
        }
        families
    }

    pub fn describe(&self) -> String {
        let q = |q: &Queue| format!("family {} queue {}", q.family, q.index);
        match self.async_compute.len() {
            0 => format!(
                "graphics and compute share {} (the device offers one queue): parts run in sequence",
                q(&self.graphics)
            ),
            n => format!(
                "graphics on {}; {n} async compute queue{} ({})",
                q(&self.graphics),
                if n == 1 { "" } else { "s" },
                self.async_compute
                    .iter()
                    .map(q)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// What the renderer needs to know about the chosen device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub name: String,
    pub device_type: vk::PhysicalDeviceType,
    pub driver: String,
    pub api_version: u32,
    pub timestamp_period_ns: f64,
    pub max_shared_memory_bytes: u32,
    pub max_workgroup_invocations: u32,
    pub max_image_dimension_2d: u32,
    pub max_image_dimension_3d: u32,
    pub max_storage_buffer_range: u32,
    /// The most texels a texel-buffer view may hold (maxTexelBufferElements).
    pub max_texel_buffer_elements: u32,
    pub descriptor_limits: DescriptorLimits,
    pub max_push_constants_size: u32,
    pub max_image_array_layers: u32,
    /// Largest single memory allocation the device supports (maxMemoryAllocationSize).
    pub max_memory_allocation_size: u64,
    pub shader_buffer_float32_atomic_add: bool,
    /// 64-bit integer atomics on storage buffers (shaderBufferInt64Atomics with shaderInt64).
    pub shader_buffer_int64_atomics: bool,
    /// Fragment shaders may write storage buffers (fragmentStoresAndAtomics).
    pub fragment_stores_and_atomics: bool,
    /// Invocations a subgroup (Vulkan 1.1's subgroupSize).
    pub subgroup_size: u32,
    /// Compute shaders may shuffle values across a subgroup (the compute stage with the basic
    /// and shuffle subgroup operations).
    pub compute_subgroup_shuffles: bool,
    /// Compute shaders may reduce values across a subgroup (the compute stage with the basic
    /// and arithmetic subgroup operations).
    pub compute_subgroup_arithmetic: bool,
    /// Fragment and compute shaders may ballot, vote and shuffle across a subgroup (both stages
    /// with the basic, ballot, vote and shuffle subgroup operations).
    pub pixel_subgroup_shuffles: bool,
    /// VK_EXT_conservative_rasterization, where the device has it (enabled): raster pipelines
    /// may overestimate coverage (every pixel a triangle touches).
    pub conservative_rasterization: Option<ConservativeRasterization>,
    /// How the per-pixel passes with two forms run ([`GpuOptions::pixel_passes`]).
    pub pixel_passes: PixelPasses,
}

/// How many descriptors of each kind one shader stage may use (maxPerStageDescriptor*), and how
/// many bindings one push-descriptor set may hold (maxPushDescriptors).
#[derive(Clone, Copy, Debug)]
pub struct DescriptorLimits {
    pub storage_buffers: u32,
    pub uniform_buffers: u32,
    /// Sampled images, combined image samplers and uniform texel buffers.
    pub sampled_images: u32,
    /// Storage images and storage texel buffers.
    pub storage_images: u32,
    /// Samplers and combined image samplers.
    pub samplers: u32,
    pub push_descriptors: u32,
}

/// What the device's conservative rasterisation does beyond the pixel square.
#[derive(Clone, Copy, Debug)]
pub struct ConservativeRasterization {
    /// The largest extra overestimation a pipeline may ask for, in pixels.
    pub max_extra_overestimation: f32,
    /// Whether triangles that become degenerate when their vertices snap are still drawn.
    pub degenerate_triangles_rasterized: bool,
}

impl DeviceInfo {
    /// Whether the device runs on the CPU (lavapipe): where the choices made per device type
    /// (the reference tracer, the LPV lookup's filter) take their CPU side.
    pub fn is_cpu(&self) -> bool {
        self.device_type == vk::PhysicalDeviceType::CPU
    }

    /// Refuse, in one line, a method (`method`) whose compute shaders sum across subgroups
    /// (`what`, the pass that does) on a device without subgroup arithmetic in compute.
    pub fn require_compute_subgroup_arithmetic(&self, method: &str, what: &str) -> GpuResult<()> {
        if self.compute_subgroup_arithmetic {
            return Ok(());
        }
        Err(GpuError::Setup(format!(
            "{method} needs subgroup arithmetic in compute shaders ({what}), which this device ({}) does not offer",
            self.name
        )))
    }

    pub fn type_name(&self) -> &'static str {
        match self.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other",
        }
    }
}

/// The owner of the instance, device and allocator; destroyed after every resource made from it.
pub struct DeviceShared {
    /// The loaded Vulkan library (kept loaded while any handle exists).
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    pub(crate) push_descriptor: ash::khr::push_descriptor::Device,
    pub(crate) debug_utils: Option<ash::ext::debug_utils::Device>,
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    debug_messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    validation: Option<Arc<ValidationLog>>,
}

impl DeviceShared {
    /// Name a Vulkan object for validation messages and GPU debuggers (no-op without debug utils).
    pub(crate) fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let (Some(utils), Ok(name)) = (&self.debug_utils, CString::new(name)) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&name);
        // SAFETY: the handle belongs to this device and the name outlives the call.
        let _ = unsafe { utils.set_debug_utils_object_name(&info) };
    }
}

impl Drop for DeviceShared {
    fn drop(&mut self) {
        // SAFETY: every resource holds an Arc to this struct, so none is alive any more; waiting
        // for idle satisfies "all submitted work must have completed" before device destruction.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.debug_messenger.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        // The messenger is gone, so the log it wrote to can be released now.
        drop(self.validation.take());
    }
}

/// The command pool of one-shot work (uploads, readbacks, tests' passes) and the one command
/// buffer it records into, reset and reused by every call. It is never freed while the device
/// lives: the Khronos validation layers before 1.3.243 (Debian 12 ships 1.3.239) erase a freed
/// command buffer's debug labels without their lock, racing their queue thread, which
/// corrupted the heap about once in six runs of tests/radiosity.rs (upstream issue
/// KhronosGroup/Vulkan-ValidationLayers#5172).
pub(crate) struct OneShot {
    pub(crate) pool: vk::CommandPool,
    pub(crate) buffer: Option<vk::CommandBuffer>,
}

/// The GPU: device, queue plan and a command pool for one-shot work (uploads and readbacks).
pub struct Gpu {
    pub(crate) shared: Arc<DeviceShared>,
    pub queues: QueuePlan,
    pub info: DeviceInfo,
    validation: Option<Arc<ValidationLog>>,
    pub(crate) one_shot: Mutex<OneShot>,
}

impl Gpu {
    pub fn new(options: &GpuOptions) -> GpuResult<Gpu> {
        ensure_runtime_dir();
        // SAFETY: loading the system Vulkan loader; its entry points are used only through `entry`.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| GpuError::Setup(format!("cannot load the Vulkan loader: {e}")))?;
        let validation = options
            .validation
            .then(|| Arc::new(ValidationLog::default()));
        let (instance, debug_messenger, has_debug_utils) =
            create_instance(&entry, validation.as_ref(), options.display)?;
        // finish_device owns the instance from here on, and destroys it if it fails.
        finish_device(
            entry,
            instance,
            debug_messenger,
            has_debug_utils,
            validation,
            options,
        )
    }

    pub fn device(&self) -> &ash::Device {
        &self.shared.device
    }

    /// Validation errors reported so far (0 when validation is off).
    pub fn validation_errors(&self) -> u32 {
        self.validation.as_ref().map_or(0, |v| v.error_count())
    }

    pub fn validation_log(&self) -> Option<&ValidationLog> {
        self.validation.as_deref()
    }

    /// The validation log, kept alive beyond the GPU: errors raised while the device and the
    /// instance are destroyed are counted too.
    pub fn shared_validation_log(&self) -> Option<Arc<ValidationLog>> {
        self.validation.clone()
    }

    pub fn validation_enabled(&self) -> bool {
        self.validation.is_some()
    }

    /// Whether optimally tiled images of `format` have every one of `features`.
    pub fn supports_format(&self, format: vk::Format, features: vk::FormatFeatureFlags) -> bool {
        // SAFETY: a query on the live physical device the instance enumerated.
        let properties = unsafe {
            self.shared
                .instance
                .get_physical_device_format_properties(self.shared.physical, format)
        };
        properties.optimal_tiling_features.contains(features)
    }

    /// Wait until the device has finished all submitted work (end of a run, before teardown).
    pub fn wait_idle(&self) -> GpuResult<()> {
        // SAFETY: no queue is being submitted to concurrently; the renderer is single-threaded.
        unsafe { self.shared.device.device_wait_idle() }.map_err(vk_err("waiting for device idle"))
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        if let Ok(OneShot { pool, .. }) = self.one_shot.get_mut() {
            // SAFETY: one-shot submissions wait on their fence before returning, so none of the
            // pool's command buffers is pending.
            unsafe {
                let _ = self.shared.device.device_wait_idle();
                self.shared.device.destroy_command_pool(*pool, None);
            }
        }
    }
}

/// Vulkan loaders and layers warn without XDG_RUNTIME_DIR; give them a private one if unset.
fn ensure_runtime_dir() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir()) {
        return;
    }
    let dir = std::env::temp_dir().join(format!("vkgi-runtime-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_ok() {
        // SAFETY: set before any Vulkan call and before this process starts other threads that
        // read the environment (the renderer creates its GPU context first).
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

type Messenger = (ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT);

fn create_instance(
    entry: &ash::Entry,
    validation: Option<&Arc<ValidationLog>>,
    display: Option<winit::raw_window_handle::RawDisplayHandle>,
) -> GpuResult<(ash::Instance, Option<Messenger>, bool)> {
    // SAFETY: plain enumeration calls on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .map_err(vk_err("enumerating instance layers"))?;
    // SAFETY: as above.
    let extensions = unsafe { entry.enumerate_instance_extension_properties(None) }
        .map_err(vk_err("enumerating instance extensions"))?;
    let has_layer = |name: &CStr| layers.iter().any(|l| l.layer_name_as_c_str() == Ok(name));
    let has_ext = |name: &CStr| {
        extensions
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(name))
    };

    let mut layer_names = Vec::new();
    if validation.is_some() {
        if !has_layer(VALIDATION_LAYER) {
            return Err(GpuError::Setup(
                "validation was requested but VK_LAYER_KHRONOS_validation is not installed \
                 (Debian package vulkan-validationlayers)"
                    .into(),
            ));
        }
        layer_names.push(VALIDATION_LAYER.as_ptr());
    }
    let has_debug_utils = has_ext(ash::ext::debug_utils::NAME);
    let mut extension_names = Vec::new();
    if has_debug_utils {
        extension_names.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    if let Some(display) = display {
        for name in super::swapchain::surface_extensions(display)? {
            if !has_ext(name) {
                return Err(GpuError::Setup(format!(
                    "the Vulkan loader lacks {}, needed to present to this display",
                    name.to_string_lossy()
                )));
            }
            extension_names.push(name.as_ptr());
        }
    }

    let app_info = vk::ApplicationInfo::default()
        .application_name(c"vkgi")
        .engine_name(c"vkgi")
        .api_version(vk::API_VERSION_1_3);
    let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut validation_features =
        vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app_info)
        .enabled_layer_names(&layer_names)
        .enabled_extension_names(&extension_names);
    if validation.is_some() {
        info = info.push_next(&mut validation_features);
    }
    // SAFETY: every pointer in `info` refers to locals that live until the call returns.
    let instance =
        unsafe { entry.create_instance(&info, None) }.map_err(vk_err("creating the instance"))?;

    let messenger = match (validation, has_debug_utils) {
        (Some(log), true) => {
            let utils = ash::ext::debug_utils::Instance::new(entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                        | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                        | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(debug_callback))
                .user_data(Arc::as_ptr(log) as *mut c_void);
            // SAFETY: the user data points at a ValidationLog kept alive (in DeviceShared) until
            // after the messenger is destroyed.
            match unsafe { utils.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((utils, m)),
                Err(e) => {
                    // SAFETY: nothing else was created from this instance yet.
                    unsafe { instance.destroy_instance(None) };
                    return Err(GpuError::Vulkan {
                        what: "creating the debug messenger".into(),
                        result: e,
                    });
                }
            }
        }
        _ => None,
    };
    Ok((instance, messenger, has_debug_utils))
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes a valid callback-data pointer for the duration of the call.
    let message = unsafe { data.as_ref() }
        // SAFETY: p_message is a NUL-terminated string owned by the layer during the call.
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        log::error!("validation: {message}");
        // SAFETY: `user` is the ValidationLog registered with this messenger, alive until after
        // the messenger is destroyed.
        if let Some(log) = unsafe { (user as *const ValidationLog).as_ref() } {
            log.record_error(message);
        }
    } else {
        log::warn!("validation: {message}");
    }
    vk::FALSE
}

fn finish_device(
    entry: ash::Entry,
    instance: ash::Instance,
    debug_messenger: Option<Messenger>,
    has_debug_utils: bool,
    validation: Option<Arc<ValidationLog>>,
    options: &GpuOptions,
) -> GpuResult<Gpu> {
    let destroy_instance = |messenger: Option<Messenger>| {
        // SAFETY: no device was created from this instance (or it was already destroyed).
        unsafe {
            if let Some((utils, m)) = messenger {
                utils.destroy_debug_utils_messenger(m, None);
            }
            instance.destroy_instance(None);
        }
    };
    let physical = match choose_physical_device(&instance, options) {
        Ok(p) => p,
        Err(e) => {
            destroy_instance(debug_messenger);
            return Err(e);
        }
    };
    let created = create_device(&instance, physical, options.display.is_some());
    let (device, queues, mut info) = match created {
        Ok(d) => d,
        Err(e) => {
            destroy_instance(debug_messenger);
            return Err(e);
        }
    };
    info.pixel_passes = options.pixel_passes.unwrap_or(info.pixel_passes);
    let allocator = Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device: physical,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    });
    let allocator = match allocator {
        Ok(a) => a,
        Err(e) => {
            // SAFETY: the device has no objects yet.
            unsafe { device.destroy_device(None) };
            destroy_instance(debug_messenger);
            return Err(GpuError::Setup(format!(
                "creating the memory allocator: {e}"
            )));
        }
    };
    let push_descriptor = ash::khr::push_descriptor::Device::new(&instance, &device);
    let debug_utils =
        has_debug_utils.then(|| ash::ext::debug_utils::Device::new(&instance, &device));
    let shared = Arc::new(DeviceShared {
        entry,
        instance,
        physical,
        device,
        push_descriptor,
        debug_utils,
        allocator: ManuallyDrop::new(Mutex::new(allocator)),
        debug_messenger,
        validation: validation.clone(),
    });
    let pool_info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(queues.graphics.family)
        .flags(
            vk::CommandPoolCreateFlags::TRANSIENT
                | vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER,
        );
    // SAFETY: valid device and create info.
    let pool = unsafe { shared.device.create_command_pool(&pool_info, None) }
        .map_err(vk_err("creating the one-shot command pool"))?;
    log::info!(
        "device: {} ({}), driver {}, Vulkan {}.{}.{}",
        info.name,
        info.type_name(),
        info.driver,
        vk::api_version_major(info.api_version),
        vk::api_version_minor(info.api_version),
        vk::api_version_patch(info.api_version)
    );
    log::info!("queue plan: {}", queues.describe());
    Ok(Gpu {
        shared,
        queues,
        info,
        validation,
        one_shot: Mutex::new(OneShot { pool, buffer: None }),
    })
}

fn device_type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

fn choose_physical_device(
    instance: &ash::Instance,
    options: &GpuOptions,
) -> GpuResult<vk::PhysicalDevice> {
    // SAFETY: enumeration on a valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(vk_err("enumerating physical devices"))?;
    let described: Vec<(vk::PhysicalDevice, String, vk::PhysicalDeviceType, u32)> = devices
        .iter()
        .map(|&d| {
            // SAFETY: `d` was just enumerated from this instance.
            let props = unsafe { instance.get_physical_device_properties(d) };
            let name = props
                .device_name_as_c_str()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            (d, name, props.device_type, props.api_version)
        })
        .filter(|(_, _, _, api)| *api >= vk::API_VERSION_1_3)
        .collect();
    if described.is_empty() {
        return Err(GpuError::Setup(
            "no Vulkan 1.3 device found (on Debian install mesa-vulkan-drivers for lavapipe)"
                .into(),
        ));
    }
    let wanted = options
        .device
        .clone()
        .or_else(|| std::env::var("VKGI_DEVICE").ok())
        .filter(|s| !s.trim().is_empty());
    if let Some(wanted) = wanted {
        let wanted_lower = wanted.to_lowercase();
        let by_index = wanted.parse::<usize>().ok().and_then(|i| described.get(i));
        let by_name = || {
            described
                .iter()
                .find(|(_, name, _, _)| name.to_lowercase().contains(&wanted_lower))
        };
        return by_index.or_else(by_name).map(|d| d.0).ok_or_else(|| {
            let names: Vec<String> = described
                .iter()
                .enumerate()
                .map(|(i, d)| format!("{i}: {}", d.1))
                .collect();
            GpuError::NoSuchDevice(format!(
                "no device matches '{wanted}' (available: {})",
                names.join(", ")
            ))
        });
    }
    let best = described
        .iter()
        .min_by_key(|d| device_type_rank(d.2))
        .map(|d| d.0);
    best.ok_or_else(|| GpuError::Setup("no Vulkan device".into()))
}

/// The graphics family, and the (family, index) of each async compute queue.
fn plan_queues(families: &[vk::QueueFamilyProperties]) -> GpuResult<(u32, Vec<(u32, u32)>)> {
    let graphics = families
        .iter()
        .position(|f| {
            f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .ok_or_else(|| GpuError::Setup("the device has no graphics+compute queue family".into()))?
        as u32;
    // Prefer a dedicated compute family (true async compute); else spare queues of the graphics
    // family; else none (everything on the graphics queue).
    let dedicated = families.iter().enumerate().find(|(_, f)| {
        f.queue_flags.contains(vk::QueueFlags::COMPUTE)
            && !f.queue_flags.contains(vk::QueueFlags::GRAPHICS)
            && f.queue_count > 0
    });
    let compute: Vec<(u32, u32)> = match dedicated {
        Some((family, props)) => (0..props.queue_count.min(MAX_ASYNC_COMPUTE_QUEUES))
            .map(|i| (family as u32, i))
            .collect(),
        None => {
            let spare = families[graphics as usize]
                .queue_count
                .saturating_sub(1)
                .min(MAX_ASYNC_COMPUTE_QUEUES);
            (1..=spare).map(|i| (graphics, i)).collect()
        }
    };
    Ok((graphics, compute))
}

fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    presents: bool,
) -> GpuResult<(ash::Device, QueuePlan, DeviceInfo)> {
    // SAFETY: queries on a physical device enumerated from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let (graphics_family, compute_queues) = plan_queues(&families)?;

    // SAFETY: as above.
    let extensions = unsafe { instance.enumerate_device_extension_properties(physical) }
        .map_err(vk_err("enumerating device extensions"))?;
    let has_ext = |name: &CStr| {
        extensions
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(name))
    };
    if !has_ext(ash::khr::push_descriptor::NAME) {
        return Err(GpuError::Setup(
            "the device lacks VK_KHR_push_descriptor, which vkgi records every pass with".into(),
        ));
    }
    let mut extension_names = vec![ash::khr::push_descriptor::NAME.as_ptr()];
    if presents {
        if !has_ext(ash::khr::swapchain::NAME) {
            return Err(GpuError::Setup(
                "the device lacks VK_KHR_swapchain, so it cannot present to a window".into(),
            ));
        }
        extension_names.push(ash::khr::swapchain::NAME.as_ptr());
    }
    let has_atomic_float = has_ext(ash::ext::shader_atomic_float::NAME);
    let conservative = has_ext(ash::ext::conservative_rasterization::NAME);
    if conservative {
        extension_names.push(ash::ext::conservative_rasterization::NAME.as_ptr());
    }
    let mut atomic_float_query = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default();
    let mut features13_query = vk::PhysicalDeviceVulkan13Features::default();
    let mut features12_query = vk::PhysicalDeviceVulkan12Features::default();
    let mut features_query = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut features13_query)
        .push_next(&mut features12_query);
    if has_atomic_float {
        features_query = features_query.push_next(&mut atomic_float_query);
    }
    // SAFETY: the pNext chain consists of locals valid for the call.
    unsafe { instance.get_physical_device_features2(physical, &mut features_query) };
    let base = features_query.features;
    let (has_dynamic_rendering, has_sync2) = (
        features13_query.dynamic_rendering == vk::TRUE,
        features13_query.synchronization2 == vk::TRUE,
    );
    let has_timeline = features12_query.timeline_semaphore == vk::TRUE;
    let int64_atomics =
        base.shader_int64 == vk::TRUE && features12_query.shader_buffer_int64_atomics == vk::TRUE;
    let atomic_add =
        has_atomic_float && atomic_float_query.shader_buffer_float32_atomic_add == vk::TRUE;
    if !(has_dynamic_rendering && has_sync2 && has_timeline) {
        return Err(GpuError::Setup(
            "the device lacks dynamicRendering, synchronization2 or timelineSemaphore".into(),
        ));
    }

    let mut queue_counts: Vec<(u32, u32)> = vec![(graphics_family, 1)];
    for &(family, index) in &compute_queues {
        match queue_counts.iter_mut().find(|(f, _)| *f == family) {
            Some(entry) => entry.1 = entry.1.max(index + 1),
            None => queue_counts.push((family, index + 1)),
        }
    }
    let priorities = [1.0f32; 1 + MAX_ASYNC_COMPUTE_QUEUES as usize];
    let queue_infos: Vec<vk::DeviceQueueCreateInfo> = queue_counts
        .iter()
        .map(|&(family, count)| {
            vk::DeviceQueueCreateInfo::default()
                .queue_family_index(family)
                .queue_priorities(&priorities[..count as usize])
        })
        .collect();

    let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true);
    let mut features12 = vk::PhysicalDeviceVulkan12Features::default()
        .timeline_semaphore(true)
        .host_query_reset(features12_query.host_query_reset == vk::TRUE)
        .shader_buffer_int64_atomics(int64_atomics);
    let mut atomic_float = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default()
        .shader_buffer_float32_atomic_add(atomic_add);
    let enabled = vk::PhysicalDeviceFeatures::default()
        .shader_float64(base.shader_float64 == vk::TRUE)
        .shader_int64(base.shader_int64 == vk::TRUE)
        // Radiosity's stereographic item buffer clips at the shooter's horizon.
        .shader_clip_distance(base.shader_clip_distance == vk::TRUE)
        .fragment_stores_and_atomics(base.fragment_stores_and_atomics == vk::TRUE)
        .shader_storage_image_write_without_format(
            base.shader_storage_image_write_without_format == vk::TRUE,
        );
    if atomic_add {
        extension_names.push(ash::ext::shader_atomic_float::NAME.as_ptr());
    }
    let mut info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .enabled_extension_names(&extension_names)
        .enabled_features(&enabled)
        .push_next(&mut features13)
        .push_next(&mut features12);
    if atomic_add {
        info = info.push_next(&mut atomic_float);
    }
    // SAFETY: all pointers in `info` refer to locals alive for the call.
    let device = unsafe { instance.create_device(physical, &info, None) }
        .map_err(vk_err("creating the logical device"))?;

    let queue = |family: u32, index: u32| Queue {
        // SAFETY: (family, index) was requested in `queue_infos`.
        raw: unsafe { device.get_device_queue(family, index) },
        family,
        index,
        timestamp_valid_bits: families[family as usize].timestamp_valid_bits,
        stages: queue_stages(families[family as usize].queue_flags),
    };
    let plan = QueuePlan {
        graphics: queue(graphics_family, 0),
        async_compute: compute_queues
            .iter()
            .map(|&(family, index)| queue(family, index))
            .collect(),
    };

    let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup_props = vk::PhysicalDeviceSubgroupProperties::default();
    let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
    let mut push_descriptor_props = vk::PhysicalDevicePushDescriptorPropertiesKHR::default();
    let mut conservative_props =
        vk::PhysicalDeviceConservativeRasterizationPropertiesEXT::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver_props)
        .push_next(&mut subgroup_props)
        .push_next(&mut maintenance3)
        .push_next(&mut push_descriptor_props);
    if conservative {
        props2 = props2.push_next(&mut conservative_props);
    }
    // SAFETY: the pNext chain is a local valid for the call.
    unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
    let props = props2.properties;
    let limits = props.limits;
    let c_str = |s: Result<&CStr, _>| s.map(|s: &CStr| s.to_string_lossy().into_owned());
    // Shaders of `stages` may use the basic subgroup operations and `operations`.
    let subgroups = |stages: vk::ShaderStageFlags, operations: vk::SubgroupFeatureFlags| {
        subgroup_props.supported_stages.contains(stages)
            && subgroup_props
                .supported_operations
                .contains(vk::SubgroupFeatureFlags::BASIC | operations)
    };
    let compute_subgroups =
        |operations: vk::SubgroupFeatureFlags| subgroups(vk::ShaderStageFlags::COMPUTE, operations);
    let info = DeviceInfo {
        name: c_str(props.device_name_as_c_str()).unwrap_or_default(),
        device_type: props.device_type,
        driver: format!(
            "{} {}",
            c_str(driver_props.driver_name_as_c_str()).unwrap_or_default(),
            c_str(driver_props.driver_info_as_c_str()).unwrap_or_default()
        )
        .trim()
        .to_string(),
        api_version: props.api_version,
        timestamp_period_ns: f64::from(limits.timestamp_period),
        max_shared_memory_bytes: limits.max_compute_shared_memory_size,
        max_workgroup_invocations: limits.max_compute_work_group_invocations,
        max_image_dimension_2d: limits.max_image_dimension2_d,
        max_image_dimension_3d: limits.max_image_dimension3_d,
        max_storage_buffer_range: limits.max_storage_buffer_range,
        max_texel_buffer_elements: limits.max_texel_buffer_elements,
        descriptor_limits: DescriptorLimits {
            storage_buffers: limits.max_per_stage_descriptor_storage_buffers,
            uniform_buffers: limits.max_per_stage_descriptor_uniform_buffers,
            sampled_images: limits.max_per_stage_descriptor_sampled_images,
            storage_images: limits.max_per_stage_descriptor_storage_images,
            samplers: limits.max_per_stage_descriptor_samplers,
            push_descriptors: push_descriptor_props.max_push_descriptors,
        },
        max_push_constants_size: limits.max_push_constants_size,
        max_image_array_layers: limits.max_image_array_layers,
        max_memory_allocation_size: maintenance3.max_memory_allocation_size,
        shader_buffer_float32_atomic_add: atomic_add,
        shader_buffer_int64_atomics: int64_atomics,
        fragment_stores_and_atomics: base.fragment_stores_and_atomics == vk::TRUE,
        subgroup_size: subgroup_props.subgroup_size,
        compute_subgroup_shuffles: compute_subgroups(vk::SubgroupFeatureFlags::SHUFFLE),
        compute_subgroup_arithmetic: compute_subgroups(vk::SubgroupFeatureFlags::ARITHMETIC),
        pixel_subgroup_shuffles: subgroups(
            vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE,
            vk::SubgroupFeatureFlags::BALLOT
                | vk::SubgroupFeatureFlags::VOTE
                | vk::SubgroupFeatureFlags::SHUFFLE,
        ),
        conservative_rasterization: conservative.then_some(ConservativeRasterization {
            max_extra_overestimation: conservative_props.max_extra_primitive_overestimation_size,
            degenerate_triangles_rasterized: conservative_props.degenerate_triangles_rasterized
                == vk::TRUE,
        }),
        pixel_passes: PixelPasses::for_device(props.device_type),
    };
    Ok((device, plan, info))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plan for `families`; fails the test if there is none.
    fn plan(families: &[vk::QueueFamilyProperties]) -> (u32, Vec<(u32, u32)>) {
        match plan_queues(families) {
            Ok(p) => p,
            Err(e) => panic!("no queue plan: {e}"),
        }
    }

    fn family(flags: vk::QueueFlags, count: u32) -> vk::QueueFamilyProperties {
        vk::QueueFamilyProperties {
            queue_flags: flags,
            queue_count: count,
            timestamp_valid_bits: 64,
            ..Default::default()
        }
    }

    const GCT: vk::QueueFlags = vk::QueueFlags::from_raw(
        vk::QueueFlags::GRAPHICS.as_raw()
            | vk::QueueFlags::COMPUTE.as_raw()
            | vk::QueueFlags::TRANSFER.as_raw(),
    );
    const CT: vk::QueueFlags = vk::QueueFlags::from_raw(
        vk::QueueFlags::COMPUTE.as_raw() | vk::QueueFlags::TRANSFER.as_raw(),
    );

    /// The per-pixel passes take the fragment form on CPU devices only, where it was measured
    /// faster (lavapipe); every kind of GPU takes the compute form.
    #[test]
    fn only_cpu_devices_run_the_fragment_form_of_the_per_pixel_passes() {
        use vk::PhysicalDeviceType as T;
        assert_eq!(PixelPasses::for_device(T::CPU), PixelPasses::Fragment);
        for gpu in [T::DISCRETE_GPU, T::INTEGRATED_GPU, T::VIRTUAL_GPU, T::OTHER] {
            assert_eq!(
                PixelPasses::for_device(gpu),
                PixelPasses::Compute,
                "{gpu:?}"
            );
        }
    }

    #[test]
    fn one_queue_leaves_no_async_compute_queue() {
        let (g, c) = plan(&[family(GCT, 1)]);
        assert_eq!(g, 0);
        assert!(c.is_empty());
    }

    #[test]
    fn a_dedicated_compute_family_gives_its_queues_up_to_the_cap() {
        let (g, c) = plan(&[
            family(GCT, 16),
            family(vk::QueueFlags::TRANSFER, 2),
            family(CT, 16),
        ]);
        assert_eq!(g, 0);
        let expected: Vec<(u32, u32)> = (0..MAX_ASYNC_COMPUTE_QUEUES).map(|i| (2, i)).collect();
        assert_eq!(c, expected);
    }

    #[test]
    fn two_compute_queues_serve_three_parts_round_robin() {
        let (_, c) = plan(&[family(GCT, 1), family(CT, 2)]);
        assert_eq!(c, vec![(1, 0), (1, 1)]);
    }

    #[test]
    fn spare_graphics_queues_serve_as_compute_queues_without_a_compute_family() {
        let (_, c) = plan(&[family(GCT, 4)]);
        assert_eq!(c, vec![(0, 1), (0, 2), (0, 3)]);
    }

    #[test]
    fn no_graphics_family_is_an_error() {
        assert!(plan_queues(&[family(CT, 4)]).is_err());
    }
}
