//! Presenting to a window (used by `vkgi view` only): the surface of a winit window and its
//! swapchain, recreated when the window changes size.

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use winit::raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::context::{DeviceShared, Gpu, Queue};
use super::{GpuError, GpuResult, vk_err};

/// The instance extensions a surface on `display` needs.
pub fn surface_extensions(display: RawDisplayHandle) -> GpuResult<Vec<&'static CStr>> {
    let platform = match display {
        RawDisplayHandle::Xlib(_) => ash::khr::xlib_surface::NAME,
        RawDisplayHandle::Xcb(_) => ash::khr::xcb_surface::NAME,
        RawDisplayHandle::Wayland(_) => ash::khr::wayland_surface::NAME,
        other => {
            return Err(GpuError::Setup(format!(
                "vkgi presents to X11 and Wayland windows only, not to {other:?}"
            )));
        }
    };
    Ok(vec![ash::khr::surface::NAME, platform])
}

/// A window's Vulkan surface.
pub struct Surface {
    /// Keeps the instance alive until the surface is destroyed.
    _shared: Arc<DeviceShared>,
    loader: ash::khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

impl Surface {
    /// The surface of a window; the GPU must have been created with `display` set, and the
    /// window must outlive the surface.
    pub fn new(gpu: &Gpu, display: RawDisplayHandle, window: RawWindowHandle) -> GpuResult<Self> {
        let shared = &gpu.shared;
        let (entry, instance) = (&shared.entry, &shared.instance);
        let raw = match (display, window) {
            (RawDisplayHandle::Xlib(d), RawWindowHandle::Xlib(w)) => {
                let dpy = d.display.map_or(std::ptr::null_mut(), |p| p.as_ptr());
                let info = vk::XlibSurfaceCreateInfoKHR::default()
                    .dpy(dpy.cast())
                    .window(w.window);
                let loader = ash::khr::xlib_surface::Instance::new(entry, instance);
                // SAFETY: the handles come from a live winit window on this display.
                unsafe { loader.create_xlib_surface(&info, None) }
            }
            (RawDisplayHandle::Xcb(d), RawWindowHandle::Xcb(w)) => {
                let connection = d.connection.map_or(std::ptr::null_mut(), |p| p.as_ptr());
                let info = vk::XcbSurfaceCreateInfoKHR::default()
                    .connection(connection)
                    .window(w.window.get());
                let loader = ash::khr::xcb_surface::Instance::new(entry, instance);
                // SAFETY: as above.
                unsafe { loader.create_xcb_surface(&info, None) }
            }
            (RawDisplayHandle::Wayland(d), RawWindowHandle::Wayland(w)) => {
                let info = vk::WaylandSurfaceCreateInfoKHR::default()
                    .display(d.display.as_ptr())
                    .surface(w.surface.as_ptr());
                let loader = ash::khr::wayland_surface::Instance::new(entry, instance);
                // SAFETY: as above.
                unsafe { loader.create_wayland_surface(&info, None) }
            }
            _ => {
                return Err(GpuError::Setup(
                    "the window is on a platform vkgi cannot present to".into(),
                ));
            }
        }
        .map_err(vk_err("creating the window surface"))?;
        Ok(Surface {
            _shared: shared.clone(),
            loader: ash::khr::surface::Instance::new(entry, instance),
            raw,
        })
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: the swapchains made from the surface are destroyed before it (they hold it).
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// A swapchain with the semaphores of acquisition (one per frame in flight) and presentation
/// (one per image, since an image's presentation may still wait on it when a frame slot is
/// reused).
pub struct Swapchain {
    shared: Arc<DeviceShared>,
    surface: Arc<Surface>,
    loader: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub vsync: bool,
    acquired: Vec<vk::Semaphore>,
    presented: Vec<vk::Semaphore>,
}

/// An image acquired for this frame.
#[derive(Clone, Copy, Debug)]
pub struct Acquired {
    pub index: u32,
    pub image: vk::Image,
    /// Signalled when the image may be written.
    pub ready: vk::Semaphore,
    /// To be signalled by the frame's last submission; presentation waits on it.
    pub rendered: vk::Semaphore,
}

impl Swapchain {
    /// A swapchain of `size` (clamped to what the surface allows) for the graphics queue.
    pub fn new(
        gpu: &Gpu,
        surface: Arc<Surface>,
        size: (u32, u32),
        vsync: bool,
        frames_in_flight: usize,
    ) -> GpuResult<Self> {
        let shared = gpu.shared.clone();
        let queue = &gpu.queues.graphics;
        // SAFETY: queries on the device's physical device and a live surface.
        let supported = unsafe {
            surface.loader.get_physical_device_surface_support(
                shared.physical,
                queue.family,
                surface.raw,
            )
        }
        .map_err(vk_err("querying surface support"))?;
        if !supported {
            return Err(GpuError::Setup(
                "the graphics queue cannot present to this window".into(),
            ));
        }
        let loader = ash::khr::swapchain::Device::new(&shared.instance, &shared.device);
        let mut chain = Swapchain {
            shared,
            surface,
            loader,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
            vsync,
            acquired: vec![vk::Semaphore::null(); frames_in_flight.max(1)],
            presented: Vec::new(),
        };
        chain.recreate(size)?;
        Ok(chain)
    }

    fn new_semaphore(&self) -> GpuResult<vk::Semaphore> {
        // SAFETY: valid create info; destroyed in Drop or recreate.
        unsafe {
            self.shared
                .device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .map_err(vk_err("creating a swapchain semaphore"))
    }

    /// Build the swapchain again for a new window size. The caller waits for the device to be
    /// idle first (no frame may still use the old images or semaphores).
    pub fn recreate(&mut self, size: (u32, u32)) -> GpuResult<()> {
        let (surface, physical) = (&self.surface, self.shared.physical);
        // SAFETY: queries on a live surface.
        let caps = unsafe {
            surface
                .loader
                .get_physical_device_surface_capabilities(physical, surface.raw)
        }
        .map_err(vk_err("querying surface capabilities"))?;
        // SAFETY: as above.
        let formats = unsafe {
            surface
                .loader
                .get_physical_device_surface_formats(physical, surface.raw)
        }
        .map_err(vk_err("querying surface formats"))?;
        // SAFETY: as above.
        let modes = unsafe {
            surface
                .loader
                .get_physical_device_surface_present_modes(physical, surface.raw)
        }
        .map_err(vk_err("querying present modes"))?;
        // The frame is already sRGB-encoded, so a UNORM format shows it unchanged.
        let format = formats
            .iter()
            .find(|f| {
                matches!(
                    f.format,
                    vk::Format::B8G8R8A8_UNORM | vk::Format::R8G8B8A8_UNORM
                )
            })
            .or(formats.first())
            .copied()
            .ok_or_else(|| GpuError::Setup("the window surface offers no format".into()))?;
        let present_mode = if self.vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .0
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .1
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(self.raw);
        // SAFETY: the surface is live; the old swapchain (if any) is retired by this call and
        // destroyed below, after the device went idle (the caller's duty).
        let raw = unsafe { self.loader.create_swapchain(&info, None) }
            .map_err(vk_err("creating the swapchain"))?;
        self.destroy_swapchain();
        self.raw = raw;
        // SAFETY: a swapchain created above.
        self.images = unsafe { self.loader.get_swapchain_images(raw) }
            .map_err(vk_err("getting swapchain images"))?;
        self.format = format.format;
        self.extent = extent;
        for _ in 0..self.images.len() {
            let semaphore = self.new_semaphore()?;
            self.presented.push(semaphore);
        }
        // Fresh acquisition semaphores too: a frame abandoned because another window's
        // swapchain was out of date may have left one signalled with no wait on it.
        for index in 0..self.acquired.len() {
            let semaphore = self.new_semaphore()?;
            let old = std::mem::replace(&mut self.acquired[index], semaphore);
            if old != vk::Semaphore::null() {
                // SAFETY: the device is idle (the caller's duty), so nothing waits on it.
                unsafe { self.shared.device.destroy_semaphore(old, None) };
            }
        }
        log::info!(
            "swapchain: {}x{} {:?}, {} images, {:?}",
            extent.width,
            extent.height,
            format.format,
            self.images.len(),
            present_mode
        );
        Ok(())
    }

    /// Acquire the next image for frame-in-flight slot `slot`; None when the swapchain is out
    /// of date (recreate it and skip the frame).
    pub fn acquire(&self, slot: usize) -> GpuResult<Option<Acquired>> {
        let ready = self.acquired[slot % self.acquired.len()];
        // SAFETY: the semaphore of this slot is unsignalled: the frame that last used the slot
        // has completed (the frame ring waited on its fence), and with it the wait on it.
        let result = unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, ready, vk::Fence::null())
        };
        match result {
            Ok((index, _suboptimal)) => Ok(Some(Acquired {
                index,
                image: self.images[index as usize],
                ready,
                rendered: self.presented[index as usize],
            })),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(e) => Err(vk_err("acquiring a swapchain image")(e)),
        }
    }

    /// Present acquired images of several swapchains at once; false when any is out of date
    /// or suboptimal (recreate them).
    pub fn present(queue: &Queue, images: &[(&Swapchain, Acquired)]) -> GpuResult<bool> {
        let Some((first, _)) = images.first() else {
            return Ok(true);
        };
        let waits: Vec<vk::Semaphore> = images.iter().map(|(_, a)| a.rendered).collect();
        let chains: Vec<vk::SwapchainKHR> = images.iter().map(|(s, _)| s.raw).collect();
        let indices: Vec<u32> = images.iter().map(|(_, a)| a.index).collect();
        let mut results = vec![vk::Result::SUCCESS; images.len()];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&chains)
            .image_indices(&indices)
            .results(&mut results);
        // SAFETY: every image was acquired and its frame submitted to signal `rendered`; the
        // queue is only used from this thread.
        match unsafe { first.loader.queue_present(queue.raw, &info) } {
            Ok(false) => Ok(results.iter().all(|r| *r == vk::Result::SUCCESS)),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR | vk::Result::SUBOPTIMAL_KHR) => {
                Ok(false)
            }
            Err(e) => Err(vk_err("presenting")(e)),
        }
    }

    fn destroy_swapchain(&mut self) {
        let device = &self.shared.device;
        // SAFETY: the device is idle (the caller's duty in recreate, Drop waits), so no
        // submission or presentation uses the swapchain or its semaphores any more.
        unsafe {
            for semaphore in self.presented.drain(..) {
                device.destroy_semaphore(semaphore, None);
            }
            if self.raw != vk::SwapchainKHR::null() {
                self.loader.destroy_swapchain(self.raw, None);
            }
        }
        self.raw = vk::SwapchainKHR::null();
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: waiting for idle before destroying what presentation may still use.
        let _ = unsafe { self.shared.device.device_wait_idle() };
        self.destroy_swapchain();
        for &semaphore in &self.acquired {
            // SAFETY: as above.
            unsafe { self.shared.device.destroy_semaphore(semaphore, None) };
        }
    }
}
