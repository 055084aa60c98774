//! Buffers, images and samplers on gpu-allocator. Each resource carries its own synchronisation
//! state (last write, readers since, image layout) so the pass recorder can place barriers.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use super::context::{DeviceShared, Gpu};
use super::{GpuError, GpuResult, vk_err};

/// What the last accesses to a resource were; see `pass::Access`.
#[derive(Clone, Copy, Debug, Default)]
pub struct SyncState {
    pub layout: vk::ImageLayout,
    pub write_stage: vk::PipelineStageFlags2,
    pub write_access: vk::AccessFlags2,
    pub read_stages: vk::PipelineStageFlags2,
    pub read_access: vk::AccessFlags2,
}

#[derive(Clone, Debug)]
pub struct BufferDesc<'a> {
    pub name: &'a str,
    pub size: u64,
    pub usage: vk::BufferUsageFlags,
    pub location: MemoryLocation,
    /// The format of a texel view over the whole buffer, for shaders that read it with texel
    /// fetches (a uniform texel buffer); None for none.
    pub texels: Option<vk::Format>,
}

impl<'a> BufferDesc<'a> {
    /// A device-local storage buffer that can also be copied to and from.
    pub fn storage(name: &'a str, size: u64) -> Self {
        BufferDesc {
            name,
            size,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            location: MemoryLocation::GpuOnly,
            texels: None,
        }
    }

    /// A storage buffer that shaders may also read as `vec4` texels (a uniform texel buffer of
    /// RGBA32F over the whole buffer).
    pub fn storage_texels(name: &'a str, size: u64) -> Self {
        BufferDesc {
            texels: Some(vk::Format::R32G32B32A32_SFLOAT),
            ..BufferDesc::storage(name, size)
        }
    }

    /// A storage buffer that shaders may also read as `uvec4` texels, bit for bit (a uniform
    /// texel buffer of RGBA32UI over the whole buffer; floats read back by uintBitsToFloat).
    pub fn storage_uint_texels(name: &'a str, size: u64) -> Self {
        BufferDesc {
            texels: Some(vk::Format::R32G32B32A32_UINT),
            ..BufferDesc::storage(name, size)
        }
    }
}

pub struct Buffer {
    shared: Arc<DeviceShared>,
    pub raw: vk::Buffer,
    allocation: Option<Allocation>,
    pub size: u64,
    pub name: String,
    pub(crate) sync: Cell<SyncState>,
    /// The texel view over the whole buffer, where its description asked for one.
    pub(crate) texel_view: Option<vk::BufferView>,
}

impl Buffer {
    /// Copy bytes into a host-visible buffer (CpuToGpu or GpuToCpu memory).
    pub fn write_mapped(&mut self, offset: u64, bytes: &[u8]) -> GpuResult<()> {
        let name = self.name.clone();
        let size = self.size as usize;
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .map(|s| &mut s[..size])
            .ok_or_else(|| GpuError::Setup(format!("buffer '{name}' is not host-visible")))?;
        let start = offset as usize;
        let end = start + bytes.len();
        if end > slice.len() {
            return Err(GpuError::Setup(format!(
                "write of {} bytes at {offset} overflows buffer '{name}' of {} bytes",
                bytes.len(),
                slice.len()
            )));
        }
        slice[start..end].copy_from_slice(bytes);
        Ok(())
    }

    /// The bytes of a host-visible buffer.
    pub fn mapped(&self) -> GpuResult<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.size as usize])
            .ok_or_else(|| GpuError::Setup(format!("buffer '{}' is not host-visible", self.name)))
    }

    /// The value at the start of a host-visible buffer (None if it is not host-visible or too
    /// small), e.g. counters a frame copied back.
    pub fn mapped_value<T: bytemuck::Pod>(&self) -> Option<T> {
        let bytes = self.mapped().ok()?;
        bytemuck::try_pod_read_unaligned(bytes.get(..std::mem::size_of::<T>())?).ok()
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer or its view (frames are
        // waited on before resources are dropped); the view goes before the buffer, and the
        // buffer before its memory.
        unsafe {
            if let Some(view) = self.texel_view.take() {
                self.shared.device.destroy_buffer_view(view, None);
            }
            self.shared.device.destroy_buffer(self.raw, None)
        };
        if let Some(allocation) = self.allocation.take()
            && let Ok(mut allocator) = self.shared.allocator.lock()
        {
            let _ = allocator.free(allocation);
        }
    }
}

#[derive(Clone, Debug)]
pub struct ImageDesc<'a> {
    pub name: &'a str,
    pub format: vk::Format,
    pub extent: vk::Extent3D,
    pub kind: vk::ImageType,
    pub layers: u32,
    /// View the layers as an array (2D_ARRAY), even when there is only one.
    pub array: bool,
    pub usage: vk::ImageUsageFlags,
    /// Render into the image (a single-layer colour attachment) through a view of this other
    /// format, e.g. the sRGB view of an 8-bit UNORM image, whose writes the attachment then
    /// encodes; every other use sees `format`. None: render through the image's own view.
    pub render_format: Option<vk::Format>,
}

impl<'a> ImageDesc<'a> {
    pub fn new_2d(
        name: &'a str,
        format: vk::Format,
        width: u32,
        height: u32,
        usage: vk::ImageUsageFlags,
    ) -> Self {
        ImageDesc {
            kind: vk::ImageType::TYPE_2D,
            ..Self::new_3d(name, format, [width, height, 1], usage)
        }
    }

    /// A 3-D image of `extent` texels.
    pub fn new_3d(
        name: &'a str,
        format: vk::Format,
        extent: [u32; 3],
        usage: vk::ImageUsageFlags,
    ) -> Self {
        ImageDesc {
            name,
            format,
            extent: vk::Extent3D {
                width: extent[0],
                height: extent[1],
                depth: extent[2],
            },
            kind: vk::ImageType::TYPE_3D,
            layers: 1,
            array: false,
            usage,
            render_format: None,
        }
    }
}

pub struct Image {
    shared: Arc<DeviceShared>,
    pub raw: vk::Image,
    /// A view of every layer (2D, 2D array or 3D).
    pub view: vk::ImageView,
    /// One 2D view per layer, for rendering into a single layer.
    pub layer_views: Vec<vk::ImageView>,
    /// The view a colour attachment renders through, in `ImageDesc::render_format` (None: `view`).
    pub render_view: Option<vk::ImageView>,
    allocation: Option<Allocation>,
    pub format: vk::Format,
    pub extent: vk::Extent3D,
    pub layers: u32,
    pub aspect: vk::ImageAspectFlags,
    pub name: String,
    pub(crate) sync: Cell<SyncState>,
}

impl Image {
    pub fn width(&self) -> u32 {
        self.extent.width
    }
    pub fn height(&self) -> u32 {
        self.extent.height
    }
    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: self.layers,
        }
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the image or its views.
        unsafe {
            for &v in self.layer_views.iter().chain(&self.render_view) {
                self.shared.device.destroy_image_view(v, None);
            }
            self.shared.device.destroy_image_view(self.view, None);
        }
        if let Some(allocation) = self.allocation.take()
            && let Ok(mut allocator) = self.shared.allocator.lock()
        {
            let _ = allocator.free(allocation);
        }
        // SAFETY: as above.
        unsafe { self.shared.device.destroy_image(self.raw, None) };
    }
}

pub struct Sampler {
    shared: Arc<DeviceShared>,
    pub raw: vk::Sampler,
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no pending command uses the sampler.
        unsafe { self.shared.device.destroy_sampler(self.raw, None) };
    }
}

/// Buffers from this size on are allocated with [`STAGGER`] bytes after them.
const STAGGER_FROM: u64 = 64 * 1024;
/// Room left after a large buffer, so that the next one does not start a multiple of a cache
/// way after it: buffers of a power-of-two size (a 32³ lattice of vec4 is 512 KiB) allocated
/// one after another would otherwise put the same element of each in the same cache set, and a
/// pass reading ten of them at once (an LPV step: three sources, three destinations, three
/// accumulations, the geometry) on a CPU device loses lines to conflicts. Three pages and five
/// lines: within a 4 KiB page (how an L1 cache is indexed), and within a 128 KiB way of an L2
/// where the memory is physically contiguous (huge pages), ten such buffers start in ten
/// different sets. Where the device aligns buffers to 4 KiB or more, the L1 part is lost.
const STAGGER: u64 = 3 * 4096 + 5 * 64;

/// `requirements` with the stagger added to a large buffer's size (the buffer keeps its own),
/// where the allocation stays within the device's `max_allocation` bytes.
fn staggered(
    mut requirements: vk::MemoryRequirements,
    max_allocation: u64,
) -> vk::MemoryRequirements {
    let stagger = STAGGER.next_multiple_of(requirements.alignment.max(1));
    if requirements.size >= STAGGER_FROM && requirements.size + stagger <= max_allocation {
        requirements.size += stagger;
    }
    requirements
}

fn is_depth_format(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D32_SFLOAT | vk::Format::D16_UNORM | vk::Format::D24_UNORM_S8_UINT
    )
}

impl Gpu {
    pub fn create_buffer(&self, desc: &BufferDesc) -> GpuResult<Buffer> {
        let device = &self.shared.device;
        let families = self.queues.families();
        let texel_usage = match desc.texels {
            Some(format) => {
                self.check_texel_count(desc, format)?;
                vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
            }
            None => vk::BufferUsageFlags::empty(),
        };
        let mut info = vk::BufferCreateInfo::default()
            .size(desc.size.max(4))
            .usage(desc.usage | texel_usage);
        info = if families.len() > 1 {
            info.sharing_mode(vk::SharingMode::CONCURRENT)
                .queue_family_indices(&families)
        } else {
            info.sharing_mode(vk::SharingMode::EXCLUSIVE)
        };
        // SAFETY: valid create info; the buffer is destroyed in Buffer::drop.
        let raw = unsafe { device.create_buffer(&info, None) }
            .map_err(vk_err(&format!("creating buffer '{}'", desc.name)))?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let requirements = staggered(requirements, self.info.max_memory_allocation_size);
        let allocation = self.allocate(desc.name, requirements, desc.location, true);
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: not bound or used yet.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: memory comes from the allocator for these requirements; bound once.
        unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_err(&format!("binding memory of buffer '{}'", desc.name)))?;
        self.shared.set_name(raw, desc.name);
        let mut buffer = Buffer {
            shared: self.shared.clone(),
            raw,
            allocation: Some(allocation),
            size: desc.size,
            name: desc.name.to_string(),
            sync: Cell::new(SyncState::default()),
            texel_view: None,
        };
        if let Some(format) = desc.texels {
            let info = vk::BufferViewCreateInfo::default()
                .buffer(raw)
                .format(format)
                .offset(0)
                .range(vk::WHOLE_SIZE);
            // SAFETY: the buffer is bound to memory and was created with texel-buffer usage; the
            // view is destroyed before the buffer in Buffer::drop.
            let view = unsafe { device.create_buffer_view(&info, None) }.map_err(vk_err(
                &format!("creating the texel view of buffer '{}'", desc.name),
            ))?;
            self.shared.set_name(view, desc.name);
            buffer.texel_view = Some(view);
        }
        Ok(buffer)
    }

    /// Refuse a texel view with more texels than the device's maxTexelBufferElements.
    fn check_texel_count(&self, desc: &BufferDesc, format: vk::Format) -> GpuResult<()> {
        let texel_bytes = match format {
            vk::Format::R32G32B32A32_SFLOAT | vk::Format::R32G32B32A32_UINT => 16,
            other => {
                return Err(GpuError::Setup(format!(
                    "buffer '{}': texel views of {other:?} are not supported",
                    desc.name
                )));
            }
        };
        let texels = desc.size / texel_bytes;
        let limit = u64::from(self.info.max_texel_buffer_elements);
        if texels > limit {
            return Err(GpuError::Setup(format!(
                "buffer '{}' holds {texels} texels, more than the device's limit of {limit} in a texel buffer",
                desc.name
            )));
        }
        Ok(())
    }

    pub fn create_image(&self, desc: &ImageDesc) -> GpuResult<Image> {
        let device = &self.shared.device;
        let families = self.queues.families();
        let view_formats: Vec<vk::Format> = match desc.render_format {
            Some(render) => vec![desc.format, render],
            None => Vec::new(),
        };
        let mut format_list = vk::ImageFormatListCreateInfo::default().view_formats(&view_formats);
        let mut info = vk::ImageCreateInfo::default()
            .image_type(desc.kind)
            .format(desc.format)
            .extent(desc.extent)
            .mip_levels(1)
            .array_layers(desc.layers)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        if desc.render_format.is_some() {
            assert!(
                desc.kind == vk::ImageType::TYPE_2D && desc.layers == 1 && !desc.array,
                "a render format is for single-layer 2-D images"
            );
            info = info
                .flags(vk::ImageCreateFlags::MUTABLE_FORMAT)
                .push_next(&mut format_list);
        }
        info = if families.len() > 1 {
            info.sharing_mode(vk::SharingMode::CONCURRENT)
                .queue_family_indices(&families)
        } else {
            info.sharing_mode(vk::SharingMode::EXCLUSIVE)
        };
        // SAFETY: valid create info; destroyed in Image::drop.
        let raw = unsafe { device.create_image(&info, None) }
            .map_err(vk_err(&format!("creating image '{}'", desc.name)))?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation =
            match self.allocate(desc.name, requirements, MemoryLocation::GpuOnly, false) {
                Ok(a) => a,
                Err(e) => {
                    // SAFETY: not bound or used yet.
                    unsafe { device.destroy_image(raw, None) };
                    return Err(e);
                }
            };
        // SAFETY: memory from the allocator for these requirements; bound once.
        unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_err(&format!("binding memory of image '{}'", desc.name)))?;
        self.shared.set_name(raw, desc.name);
        let aspect = if is_depth_format(desc.format) {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let array = desc.array || desc.layers > 1;
        let view_type = match (desc.kind, array) {
            (vk::ImageType::TYPE_3D, _) => vk::ImageViewType::TYPE_3D,
            (_, false) => vk::ImageViewType::TYPE_2D,
            (_, true) => vk::ImageViewType::TYPE_2D_ARRAY,
        };
        let make_view = |view_type, base_layer, layer_count, format| {
            // A render view is for rendering only: its format need not support the image's
            // other uses (an sRGB format cannot be a storage image).
            let mut render_usage = vk::ImageViewUsageCreateInfo::default()
                .usage(vk::ImageUsageFlags::COLOR_ATTACHMENT);
            let mut info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(view_type)
                .format(format)
                .subresource_range(vk::ImageSubresourceRange {
                    aspect_mask: aspect,
                    base_mip_level: 0,
                    level_count: 1,
                    base_array_layer: base_layer,
                    layer_count,
                });
            if format != desc.format {
                info = info.push_next(&mut render_usage);
            }
            // SAFETY: the image is bound to memory and the range lies inside it.
            unsafe { device.create_image_view(&info, None) }
                .map_err(vk_err(&format!("creating a view of image '{}'", desc.name)))
        };
        let mut image = Image {
            shared: self.shared.clone(),
            raw,
            view: vk::ImageView::null(),
            layer_views: Vec::new(),
            render_view: None,
            allocation: Some(allocation),
            format: desc.format,
            extent: desc.extent,
            layers: desc.layers,
            aspect,
            name: desc.name.to_string(),
            sync: Cell::new(SyncState::default()),
        };
        // From here on, Image::drop cleans up whatever views were made.
        image.view = make_view(view_type, 0, desc.layers, desc.format)?;
        if array {
            for layer in 0..desc.layers {
                let view = make_view(vk::ImageViewType::TYPE_2D, layer, 1, desc.format)?;
                image.layer_views.push(view);
            }
        }
        if let Some(render) = desc.render_format {
            image.render_view = Some(make_view(view_type, 0, 1, render)?);
        }
        Ok(image)
    }

    /// A sampler; `compare` makes a depth-comparison sampler.
    pub fn create_sampler(
        &self,
        filter: vk::Filter,
        address: vk::SamplerAddressMode,
    ) -> GpuResult<Sampler> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address)
            .border_color(vk::BorderColor::FLOAT_TRANSPARENT_BLACK)
            .max_lod(0.0);
        // SAFETY: valid create info; destroyed in Sampler::drop.
        let raw = unsafe { self.shared.device.create_sampler(&info, None) }
            .map_err(vk_err("creating a sampler"))?;
        Ok(Sampler {
            shared: self.shared.clone(),
            raw,
        })
    }

    fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> GpuResult<Allocation> {
        let mut allocator = self
            .shared
            .allocator
            .lock()
            .map_err(|_| GpuError::Setup("allocator lock poisoned".into()))?;
        allocator
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| GpuError::Allocation {
                what: name.to_string(),
                message: e.to_string(),
            })
    }

    /// A device-local buffer holding `data`, uploaded through a staging buffer.
    pub fn upload_buffer(
        &self,
        name: &str,
        usage: vk::BufferUsageFlags,
        data: &[u8],
    ) -> GpuResult<Buffer> {
        let buffer = self.create_buffer(&BufferDesc {
            name,
            size: data.len() as u64,
            usage: usage | vk::BufferUsageFlags::TRANSFER_DST,
            location: MemoryLocation::GpuOnly,
            texels: None,
        })?;
        if !data.is_empty() {
            self.write_buffer(&buffer, data)?;
        }
        Ok(buffer)
    }

    /// A device-local storage buffer holding `data` (never empty: at least 16 zero bytes).
    pub fn upload_storage(&self, name: &str, data: &[u8]) -> GpuResult<Buffer> {
        let padded;
        let data = if data.is_empty() {
            padded = [0u8; 16];
            &padded[..]
        } else {
            data
        };
        self.upload_buffer(
            name,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            data,
        )
    }

    /// A device-local storage buffer of `count` items made by `item(i)`, written straight into
    /// the staging memory a chunk at a time (no full copy of the data on the host first).
    pub fn upload_storage_items<T: bytemuck::Pod>(
        &self,
        name: &str,
        count: usize,
        item: impl Fn(usize) -> T,
    ) -> GpuResult<Buffer> {
        if count == 0 {
            return self.upload_storage(name, &[]);
        }
        self.upload_items(name, count, None, item)
    }

    /// [`Gpu::upload_storage_items`] of at least one item, which shaders read as texels of
    /// `format` (a uniform texel buffer over the whole buffer).
    pub fn upload_texel_items<T: bytemuck::Pod>(
        &self,
        name: &str,
        count: usize,
        format: vk::Format,
        item: impl Fn(usize) -> T,
    ) -> GpuResult<Buffer> {
        self.upload_items(name, count.max(1), Some(format), item)
    }

    fn upload_items<T: bytemuck::Pod>(
        &self,
        name: &str,
        count: usize,
        texels: Option<vk::Format>,
        item: impl Fn(usize) -> T,
    ) -> GpuResult<Buffer> {
        let size = std::mem::size_of::<T>();
        let buffer = self.create_buffer(&BufferDesc {
            texels,
            ..BufferDesc::storage(name, (count * size) as u64)
        })?;
        let staging_name = format!("{name} (staging)");
        let mut staging = self.create_buffer(&BufferDesc {
            name: &staging_name,
            size: buffer.size,
            usage: vk::BufferUsageFlags::TRANSFER_SRC,
            location: MemoryLocation::CpuToGpu,
            texels: None,
        })?;
        const CHUNK: usize = 1 << 14;
        let mut chunk: Vec<T> = Vec::with_capacity(CHUNK.min(count));
        for start in (0..count).step_by(CHUNK) {
            chunk.clear();
            chunk.extend((start..(start + CHUNK).min(count)).map(&item));
            staging.write_mapped((start * size) as u64, bytemuck::cast_slice(&chunk))?;
        }
        self.one_shot(|rec| {
            rec.copy_buffer("upload", &staging, &buffer, buffer.size);
            Ok(())
        })?;
        Ok(buffer)
    }

    /// A device-local uniform buffer holding `data` (constants read by every invocation).
    pub fn upload_uniform(&self, name: &str, data: &[u8]) -> GpuResult<Buffer> {
        self.upload_buffer(name, vk::BufferUsageFlags::UNIFORM_BUFFER, data)
    }

    /// Overwrite the start of a device-local buffer (which must allow TRANSFER_DST) with `data`.
    pub fn write_buffer(&self, buffer: &Buffer, data: &[u8]) -> GpuResult<()> {
        let staging_name = format!("{} (staging)", buffer.name);
        let mut staging = self.create_buffer(&BufferDesc {
            name: &staging_name,
            size: data.len() as u64,
            usage: vk::BufferUsageFlags::TRANSFER_SRC,
            location: MemoryLocation::CpuToGpu,
            texels: None,
        })?;
        staging.write_mapped(0, data)?;
        self.one_shot(|rec| {
            rec.copy_buffer("upload", &staging, buffer, data.len() as u64);
            Ok(())
        })
    }

    /// The contents of a buffer, copied back through a host-visible staging buffer.
    pub fn read_buffer(&self, buffer: &Buffer) -> GpuResult<Vec<u8>> {
        let staging_name = format!("{} (readback)", buffer.name);
        let staging = self.create_buffer(&BufferDesc {
            name: &staging_name,
            size: buffer.size,
            usage: vk::BufferUsageFlags::TRANSFER_DST,
            location: MemoryLocation::GpuToCpu,
            texels: None,
        })?;
        self.one_shot(|rec| {
            rec.copy_buffer("readback", buffer, &staging, buffer.size);
            rec.host_read(&staging);
            Ok(())
        })?;
        Ok(staging.mapped()?.to_vec())
    }

    /// The texels of every layer of a colour image, tightly packed, layer after layer.
    pub fn read_image(&self, image: &Image) -> GpuResult<Vec<u8>> {
        let bytes = u64::from(image.width())
            * u64::from(image.height())
            * u64::from(image.extent.depth)
            * u64::from(image.layers)
            * format_bytes(image.format)?;
        let staging = self.create_buffer(&BufferDesc {
            name: "image readback",
            size: bytes,
            usage: vk::BufferUsageFlags::TRANSFER_DST,
            location: MemoryLocation::GpuToCpu,
            texels: None,
        })?;
        self.one_shot(|rec| {
            rec.copy_image_to_buffer("readback", image, &staging);
            rec.host_read(&staging);
            Ok(())
        })?;
        Ok(staging.mapped()?.to_vec())
    }
}

/// Bytes per texel of the formats vkgi reads back.
pub fn format_bytes(format: vk::Format) -> GpuResult<u64> {
    Ok(match format {
        vk::Format::R8G8B8A8_UNORM | vk::Format::R8G8B8A8_SRGB | vk::Format::R32_SFLOAT => 4,
        vk::Format::D32_SFLOAT | vk::Format::R32_UINT => 4,
        vk::Format::R16G16B16A16_SFLOAT => 8,
        vk::Format::R32G32B32A32_SFLOAT => 16,
        other => {
            return Err(GpuError::Setup(format!(
                "no readback size known for {other:?}"
            )));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn requirements(size: u64, alignment: u64) -> vk::MemoryRequirements {
        vk::MemoryRequirements {
            size,
            alignment,
            memory_type_bits: 1,
        }
    }

    #[test]
    fn large_buffers_are_staggered_within_the_allocation_limit() {
        let lattice = 32 * 32 * 32 * 16;
        assert_eq!(
            staggered(requirements(lattice, 64), u64::MAX).size,
            lattice + STAGGER
        );
        // The stagger keeps the allocation's alignment.
        assert_eq!(
            staggered(requirements(lattice, 4096), u64::MAX).size,
            lattice + 16384
        );
        assert_eq!(staggered(requirements(4096, 64), u64::MAX).size, 4096);
        assert_eq!(
            staggered(requirements(lattice, 64), lattice + 100).size,
            lattice
        );
    }

    #[test]
    fn ten_power_of_two_buffers_in_a_row_start_in_ten_cache_sets() {
        // 512 KiB buffers one after another: their starts in a 128 KiB L2 way and a 4 KiB L1
        // way, in 64-byte lines, all differ.
        let step = 32 * 32 * 32 * 16 + STAGGER;
        for way in [128 * 1024, 4096] {
            let mut sets: Vec<u64> = (0..10).map(|k| (k * step % way) / 64).collect();
            sets.sort_unstable();
            sets.dedup();
            assert_eq!(sets.len(), 10, "way {way}");
        }
    }
}
