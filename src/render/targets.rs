//! What a frame renders into: eyes, views and their G-buffers. These sit below the GI methods
//! (src/gi/), which read a view's G-buffer and add to its HDR image.

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::InputError;
use crate::gpu::{Gpu, GpuResult, Image, ImageDesc};
use crate::scene::{Camera, Scene};

/// Largest image side vkgi renders (also bounded by the device's limit).
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// Formats of the G-buffer's colour attachments: position, normal, albedo, emission, glossy
/// reflectance and roughness.
pub const GBUFFER_FORMATS: [vk::Format; 5] = [
    vk::Format::R32G32B32A32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
];

/// Format of the G-buffer's depth, which per-pixel passes of covered pixels only test against
/// (`full_screen::Pixels::Covered`).
pub const GBUFFER_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Format of a view's linear HDR image.
pub const HDR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// Format of a view's tone-mapped 8-bit image: sRGB-encoded bytes, read, copied and stored as
/// they are.
pub const LDR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// The format tone mapping renders the 8-bit image through: the attachment encodes sRGB (on
/// lavapipe 40% less time than the shader's `pow`: docs/performance-log.md, "The tone map
/// through an sRGB view").
pub const LDR_RENDER_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// The attachments the G-buffer pass writes and lighting passes read.
pub struct GBuffer {
    /// xyz world position, w = 1 where a surface was hit, 0 for background.
    pub position: Image,
    /// xyz unit normal facing the camera.
    pub normal: Image,
    pub albedo: Image,
    pub emission: Image,
    /// rgb reflectance of the glossy lobe, a = roughness (src/scene/brdf.rs).
    pub specular: Image,
    pub depth: Image,
}

/// Where a view looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// World to clip space (Vulkan: depth 0..1, y down).
    pub view_projection: Mat4,
    pub position: Vec3,
}

impl Eye {
    /// The eye of a pinhole camera for an image of `width` x `height`, with clip planes that
    /// enclose the scene.
    pub fn from_camera(camera: &Camera, scene: &Scene, width: u32, height: u32) -> Eye {
        let aspect = width as f32 / height.max(1) as f32;
        Eye {
            view_projection: camera.view_projection(aspect, scene.bounds_min, scene.bounds_max),
            position: camera.position,
        }
    }
}

/// One view of the frame: its eye, G-buffer and output images.
pub struct View {
    pub eye: Eye,
    pub gbuffer: GBuffer,
    /// Linear HDR radiance (the image every error metric is computed on).
    pub hdr: Image,
    /// Tone-mapped, sRGB-encoded 8-bit output.
    pub ldr: Image,
}

impl View {
    /// A view's G-buffer and images of `width` x `height`.
    pub fn new(gpu: &Gpu, width: u32, height: u32, eye: Eye) -> GpuResult<View> {
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST;
        let image = |name: &str, format: vk::Format, usage: vk::ImageUsageFlags| {
            gpu.create_image(&ImageDesc::new_2d(name, format, width, height, usage))
        };
        let gbuffer = GBuffer {
            position: image("g-buffer position", GBUFFER_FORMATS[0], attachment)?,
            normal: image("g-buffer normal", GBUFFER_FORMATS[1], attachment)?,
            albedo: image("g-buffer albedo", GBUFFER_FORMATS[2], attachment)?,
            emission: image("g-buffer emission", GBUFFER_FORMATS[3], attachment)?,
            specular: image("g-buffer specular", GBUFFER_FORMATS[4], attachment)?,
            depth: image(
                "g-buffer depth",
                GBUFFER_DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            )?,
        };
        // A scene without emission or glossy lobes never writes those two targets
        // (src/render/passes.rs), and whoever reads them reads zero.
        gpu.one_shot(|rec| {
            rec.clear_image("clear g-buffer emission", &gbuffer.emission, [0.0; 4]);
            rec.clear_image("clear g-buffer specular", &gbuffer.specular, [0.0; 4]);
            Ok(())
        })?;
        // Render targets too: the LPV lookup adds to the HDR image by blending, tone mapping
        // renders the 8-bit one through its sRGB view (src/render/full_screen.rs).
        let storage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        Ok(View {
            eye,
            gbuffer,
            hdr: image(
                "hdr radiance",
                HDR_FORMAT,
                storage | vk::ImageUsageFlags::COLOR_ATTACHMENT,
            )?,
            ldr: gpu.create_image(&ImageDesc {
                render_format: Some(LDR_RENDER_FORMAT),
                ..ImageDesc::new_2d(
                    "ldr output",
                    LDR_FORMAT,
                    width,
                    height,
                    storage | vk::ImageUsageFlags::COLOR_ATTACHMENT,
                )
            })?,
        })
    }

    pub fn width(&self) -> u32 {
        self.hdr.width()
    }

    pub fn height(&self) -> u32 {
        self.hdr.height()
    }
}

/// Largest single image or buffer vkgi allocates (also bounded by the device's
/// maxMemoryAllocationSize), so a scene with many lights is refused up front, with the limit
/// named, instead of failing allocation half-way.
pub const MAX_RESOURCE_BYTES: u64 = 1 << 30;

/// Check a layered image of `layers` layers of `side`² texels of `bytes_per_texel` against the
/// device's layer limit and vkgi's memory limit; `what` and `fix` say what it is and what to
/// change.
pub fn check_layered_image(
    gpu: &Gpu,
    what: &str,
    (side, layers, bytes_per_texel): (u32, u32, u64),
    fix: &str,
) -> Result<(), InputError> {
    let max_layers = gpu.info.max_image_array_layers;
    if layers > max_layers {
        return Err(InputError::new(format!(
            "{what} needs {layers} layers, over the device's limit of {max_layers} ({fix})"
        )));
    }
    let bytes = u64::from(side) * u64::from(side) * u64::from(layers) * bytes_per_texel;
    let limit = MAX_RESOURCE_BYTES.min(gpu.info.max_memory_allocation_size.max(1));
    if bytes > limit {
        return Err(InputError::new(format!(
            "{what} needs {layers} layers of {side}x{side} ({} MiB), over the limit of {} MiB ({fix})",
            bytes >> 20,
            limit >> 20
        )));
    }
    Ok(())
}

/// Check a buffer of `bytes` against the device's storage-buffer range and vkgi's memory limit.
pub fn check_buffer(gpu: &Gpu, what: &str, bytes: u64) -> Result<(), InputError> {
    let limit = MAX_RESOURCE_BYTES
        .min(u64::from(gpu.info.max_storage_buffer_range))
        .min(gpu.info.max_memory_allocation_size.max(1));
    if bytes > limit {
        return Err(InputError::new(format!(
            "{what} needs {} MiB, over the limit of {} MiB",
            bytes >> 20,
            limit >> 20
        )));
    }
    Ok(())
}

/// Check a buffer of `bytes` that shaders also read as 16-byte texels against
/// [`check_buffer`]'s limits and the device's most texels in a texel buffer.
pub fn check_texel_buffer(gpu: &Gpu, what: &str, bytes: u64) -> Result<(), InputError> {
    check_buffer(gpu, what, bytes)?;
    let limit = gpu.info.max_texel_buffer_elements;
    if bytes.div_ceil(16) > u64::from(limit) {
        return Err(InputError::new(format!(
            "{what} needs {} texels of 16 bytes, over the device's limit of {limit} in a texel buffer",
            bytes.div_ceil(16)
        )));
    }
    Ok(())
}

/// Check an image size against vkgi's and the device's limits.
pub fn check_image_size(gpu: &Gpu, width: u32, height: u32) -> Result<(), InputError> {
    let limit = MAX_IMAGE_SIDE.min(gpu.info.max_image_dimension_2d);
    if width == 0 || height == 0 || width > limit || height > limit {
        return Err(InputError::new(format!(
            "image size {width}x{height} is out of range: each side must be 1..={limit}"
        )));
    }
    Ok(())
}
