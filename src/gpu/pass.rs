//! The one place a pass is recorded. A pass is declared in one expression (name, pipeline,
//! bindings with read/write intent, push constants, size); the recorder checks the bindings and
//! push constants against the shader's interface, places the barriers the declared accesses
//! need, and wraps the work in a debug label and a timestamp scope tagged with the recorder's
//! context (method, stage, part, step), so no pass can forget any of them.

use ash::vk::{self, Handle};

use super::context::{Gpu, Queue};
use super::memory::{Buffer, Image, SyncState};
use super::pipeline::{ComputePipeline, Depth, PipelineCore, RasterPipeline};
use super::profiler::FrameQueries;
use super::push::{self, PushConstants};
use super::reflect::DescriptorKind;
use super::scope::{Part, ScopeTag};
use super::{GpuError, GpuResult};

/// How a pass touches a resource; decides the pipeline stage, access mask and image layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    ComputeRead,
    /// Read and write from a compute shader (storage).
    ComputeWrite,
    /// Sampled read (texture, or a uniform texel buffer's texel fetch) from a compute shader.
    ComputeSampled,
    /// Storage-buffer read in the vertex or fragment stage.
    GraphicsRead,
    /// Storage read and write in the vertex or fragment stage (fragment shaders need
    /// fragmentStoresAndAtomics, which vkgi enables where the device has it; vertex shaders
    /// would need vertexPipelineStoresAndAtomics, which it does not enable, so the validation
    /// layers reject a vertex-stage write).
    GraphicsWrite,
    /// Sampled read (texture) in the vertex or fragment stage.
    GraphicsSampled,
    ColorAttachment,
    DepthAttachment,
    /// A depth attachment only tested against (`Depth::Covered`).
    DepthTest,
    TransferRead,
    TransferWrite,
    HostRead,
    /// Draw parameters read by an indirect draw.
    IndirectRead,
}

impl Access {
    fn stage_access_layout(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout) {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        match self {
            Access::ComputeRead => (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ, L::GENERAL),
            Access::ComputeWrite => (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
                L::GENERAL,
            ),
            Access::ComputeSampled => (
                S::COMPUTE_SHADER,
                A::SHADER_SAMPLED_READ,
                L::SHADER_READ_ONLY_OPTIMAL,
            ),
            Access::GraphicsRead => (
                S::VERTEX_SHADER | S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_READ,
                L::GENERAL,
            ),
            Access::GraphicsWrite => (
                S::VERTEX_SHADER | S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
                L::GENERAL,
            ),
            Access::GraphicsSampled => (
                S::VERTEX_SHADER | S::FRAGMENT_SHADER,
                A::SHADER_SAMPLED_READ,
                L::SHADER_READ_ONLY_OPTIMAL,
            ),
            Access::ColorAttachment => (
                S::COLOR_ATTACHMENT_OUTPUT,
                A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
                L::COLOR_ATTACHMENT_OPTIMAL,
            ),
            Access::DepthAttachment => (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
                L::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            Access::DepthTest => (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ,
                L::DEPTH_READ_ONLY_OPTIMAL,
            ),
            Access::TransferRead => (S::ALL_TRANSFER, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
            Access::TransferWrite => (S::ALL_TRANSFER, A::TRANSFER_WRITE, L::TRANSFER_DST_OPTIMAL),
            Access::HostRead => (S::HOST, A::HOST_READ, L::GENERAL),
            Access::IndirectRead => (S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ, L::GENERAL),
        }
    }

    fn writes(self) -> bool {
        matches!(
            self,
            Access::ComputeWrite
                | Access::GraphicsWrite
                | Access::ColorAttachment
                | Access::DepthAttachment
                | Access::TransferWrite
        )
    }
}

/// The barrier, if any, that must precede `access` to a resource in state `state`; updates the
/// state. Read-after-write and layout changes wait on the last write; writes also wait on every
/// read since it (write-after-read); reads already made visible need nothing.
fn transition(
    state: &mut SyncState,
    access: Access,
    is_image: bool,
    queue_stages: vk::PipelineStageFlags2,
) -> Option<(
    vk::PipelineStageFlags2,
    vk::AccessFlags2,
    vk::PipelineStageFlags2,
    vk::AccessFlags2,
    vk::ImageLayout,
)> {
    let (stage, mask, layout) = access.stage_access_layout();
    let old_layout = state.layout;
    let layout_change = is_image && state.layout != layout;
    if access.writes() || layout_change {
        let (src_stage, src_access) = source_on_queue(
            state.write_stage | state.read_stages,
            state.write_stage,
            state.write_access,
            queue_stages,
        );
        *state = SyncState {
            layout: if is_image {
                layout
            } else {
                vk::ImageLayout::UNDEFINED
            },
            write_stage: stage,
            write_access: if access.writes() {
                mask
            } else {
                vk::AccessFlags2::NONE
            },
            read_stages: if access.writes() {
                vk::PipelineStageFlags2::NONE
            } else {
                stage
            },
            read_access: if access.writes() {
                vk::AccessFlags2::NONE
            } else {
                mask
            },
        };
        return Some((src_stage, src_access, stage, mask, old_layout));
    }
    if state.read_stages.contains(stage) && state.read_access.contains(mask) {
        return None;
    }
    // A write on another queue (none of this queue's stages) is the semaphore's to order; an
    // access's stages are all graphics or none, so a kept stage keeps its access.
    let src_stage = state.write_stage & queue_stages;
    let barrier =
        (!src_stage.is_empty()).then_some((src_stage, state.write_access, stage, mask, old_layout));
    state.read_stages |= stage;
    state.read_access |= mask;
    barrier
}

/// The pipeline stages a barrier recorded on a queue of a family with `flags` may name: a family
/// without graphics (a dedicated async compute family) runs no vertex, fragment or attachment
/// stage, and one without compute no compute shader.
pub fn queue_stages(flags: vk::QueueFlags) -> vk::PipelineStageFlags2 {
    use vk::PipelineStageFlags2 as S;
    let mut stages = S::from_raw(u64::MAX);
    if !flags.contains(vk::QueueFlags::GRAPHICS) {
        stages &= !(S::VERTEX_INPUT
            | S::INDEX_INPUT
            | S::VERTEX_ATTRIBUTE_INPUT
            | S::VERTEX_SHADER
            | S::TESSELLATION_CONTROL_SHADER
            | S::TESSELLATION_EVALUATION_SHADER
            | S::GEOMETRY_SHADER
            | S::PRE_RASTERIZATION_SHADERS
            | S::FRAGMENT_SHADER
            | S::EARLY_FRAGMENT_TESTS
            | S::LATE_FRAGMENT_TESTS
            | S::COLOR_ATTACHMENT_OUTPUT
            | S::ALL_GRAPHICS);
    }
    if !flags.contains(vk::QueueFlags::COMPUTE) {
        stages &= !S::COMPUTE_SHADER;
    }
    stages
}

/// A barrier's source: `stages` (the last write's stage `write_stage`, with its access
/// `write_access`, and any reads since), as a queue that runs only `queue_stages` may name them.
/// A resource's last accesses may have run on another queue (the lookup's fragment shader reads
/// a lattice on the graphics queue that an async compute queue writes in the next frame): the
/// semaphore the part waits on orders those and makes their writes visible, and a barrier naming
/// their stages would be invalid on this queue, so they leave it, and with the write's stage its
/// access (every access's stages are all graphics or none, so a kept access keeps its stages).
/// Where none is left the source is every command, so that a layout change still waits for the
/// semaphore's wait (whose stage is every command) rather than for nothing.
fn source_on_queue(
    stages: vk::PipelineStageFlags2,
    write_stage: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    queue_stages: vk::PipelineStageFlags2,
) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
    let kept = stages & queue_stages;
    if kept.is_empty() && !stages.is_empty() {
        return (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::NONE,
        );
    }
    let access = match (write_stage & queue_stages).is_empty() {
        true => vk::AccessFlags2::NONE,
        false => write_access,
    };
    (kept, access)
}

/// A resource a pass binds, with what the pass does to it.
#[derive(Clone, Copy)]
pub enum Binding<'r> {
    StorageBuffer {
        binding: u32,
        buffer: &'r Buffer,
        write: bool,
    },
    UniformBuffer {
        binding: u32,
        buffer: &'r Buffer,
    },
    StorageImage {
        binding: u32,
        image: &'r Image,
        write: bool,
    },
    SampledImage {
        binding: u32,
        image: &'r Image,
        sampler: vk::Sampler,
    },
    /// A buffer read with texel fetches through its texel view (`samplerBuffer`).
    Texels {
        binding: u32,
        buffer: &'r Buffer,
    },
}

impl<'r> Binding<'r> {
    pub fn read(binding: u32, buffer: &'r Buffer) -> Self {
        Binding::StorageBuffer {
            binding,
            buffer,
            write: false,
        }
    }
    pub fn write(binding: u32, buffer: &'r Buffer) -> Self {
        Binding::StorageBuffer {
            binding,
            buffer,
            write: true,
        }
    }
    pub fn uniform(binding: u32, buffer: &'r Buffer) -> Self {
        Binding::UniformBuffer { binding, buffer }
    }
    pub fn image_read(binding: u32, image: &'r Image) -> Self {
        Binding::StorageImage {
            binding,
            image,
            write: false,
        }
    }
    pub fn image_write(binding: u32, image: &'r Image) -> Self {
        Binding::StorageImage {
            binding,
            image,
            write: true,
        }
    }
    pub fn sampled(binding: u32, image: &'r Image, sampler: &super::Sampler) -> Self {
        Binding::SampledImage {
            binding,
            image,
            sampler: sampler.raw,
        }
    }

    /// A buffer made with a texel view ([`super::BufferDesc::storage_texels`]), read with
    /// texel fetches.
    pub fn texels(binding: u32, buffer: &'r Buffer) -> Self {
        Binding::Texels { binding, buffer }
    }

    fn number(&self) -> u32 {
        match self {
            Binding::StorageBuffer { binding, .. }
            | Binding::UniformBuffer { binding, .. }
            | Binding::StorageImage { binding, .. }
            | Binding::SampledImage { binding, .. }
            | Binding::Texels { binding, .. } => *binding,
        }
    }

    /// For storage bindings, whether the pass declares that it writes them.
    fn declared_write(&self) -> Option<bool> {
        match self {
            Binding::StorageBuffer { write, .. } | Binding::StorageImage { write, .. } => {
                Some(*write)
            }
            Binding::UniformBuffer { .. }
            | Binding::SampledImage { .. }
            | Binding::Texels { .. } => None,
        }
    }

    fn kind(&self) -> DescriptorKind {
        match self {
            Binding::StorageBuffer { .. } => DescriptorKind::StorageBuffer,
            Binding::UniformBuffer { .. } => DescriptorKind::UniformBuffer,
            Binding::StorageImage { .. } => DescriptorKind::StorageImage,
            Binding::SampledImage { .. } => DescriptorKind::CombinedImageSampler,
            Binding::Texels { .. } => DescriptorKind::UniformTexelBuffer,
        }
    }
}

/// A compute dispatch, declared in one expression.
pub struct ComputePass<'p> {
    /// The pass, without part, step or layer (the recorder's context adds those).
    pub name: &'static str,
    pub pipeline: &'p ComputePipeline,
    pub bindings: &'p [Binding<'p>],
    pub push: &'p dyn PushConstants,
    /// Threads to run along x, y, z; the workgroup count is rounded up from these.
    pub threads: [u32; 3],
}

/// What a raster pass draws: pulled vertices, no vertex buffers.
#[derive(Clone, Copy)]
pub enum Draw<'p> {
    /// This many vertices (none: the attachments are only cleared).
    Vertices(u32),
    /// The `VkDrawIndirectCommand` at byte `offset` of `buffer`, written by an earlier pass.
    Indirect { buffer: &'p Buffer, offset: u64 },
}

/// A draw into colour and depth attachments, cleared first unless `keep_contents` says to draw
/// over what they hold.
pub struct RasterPass<'p> {
    /// The pass, without part, step or layer (the recorder's context adds those).
    pub name: &'static str,
    pub pipeline: &'p RasterPipeline,
    pub bindings: &'p [Binding<'p>],
    pub push: &'p dyn PushConstants,
    /// Colour attachments, the layer rendered into, and their clear colours.
    pub color: &'p [(&'p Image, u32, [f32; 4])],
    /// Depth attachment and the layer rendered into; what the pipeline's `Depth` says: cleared
    /// and written (`Nearest`, unless the pass keeps its contents), or read as an earlier pass
    /// left it (`Covered`).
    pub depth: Option<(&'p Image, u32)>,
    pub draw: Draw<'p>,
    /// Keep the attachments' contents (the clear values are then unused).
    pub keep_contents: bool,
}

/// The view of one layer of `image` an attachment renders through (its render view if it has
/// one, else the layer's, else the whole image's).
fn layer_view(image: &Image, layer: u32) -> vk::ImageView {
    image.render_view.unwrap_or_else(|| {
        image
            .layer_views
            .get(layer as usize)
            .copied()
            .unwrap_or(image.view)
    })
}

enum Resource<'r> {
    Buffer(&'r Buffer),
    Image(&'r Image),
}

impl Resource<'_> {
    /// The resource's key and name.
    fn key_and_name(&self) -> (ResourceKey, &str) {
        match self {
            Resource::Buffer(b) => (
                ResourceKey {
                    handle: b.raw.as_raw(),
                    image: false,
                },
                &b.name,
            ),
            Resource::Image(i) => (
                ResourceKey {
                    handle: i.raw.as_raw(),
                    image: true,
                },
                &i.name,
            ),
        }
    }
}

/// Which resource: its Vulkan handle, and whether it is an image (handles of different kinds may
/// be equal).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ResourceKey {
    pub handle: u64,
    pub image: bool,
}

/// A resource an independent part used ([`Recorder::take_part_uses`]): which, its name, and
/// whether any of the part's accesses wrote it (an image's layout change counts: it rewrites the
/// image).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResourceUse {
    pub key: ResourceKey,
    pub name: String,
    pub writes: bool,
}

/// Whether no buffer appears twice (a pass that writes one buffer twice would need a barrier
/// between the writes).
fn all_distinct(mut buffers: impl Iterator<Item = vk::Buffer>) -> bool {
    let mut seen = std::collections::HashSet::new();
    buffers.all(|buffer| seen.insert(buffer))
}

/// Records passes into one command buffer of one queue family, tagging each with its context.
pub struct Recorder<'a> {
    gpu: &'a Gpu,
    cmd: vk::CommandBuffer,
    /// The queue the commands are for: its family's timestamps, and the stages its family runs
    /// ([`Queue::stages`]), the only ones its barriers name.
    queue: Queue,
    timer: Option<&'a mut FrameQueries>,
    context: ScopeTag,
    /// The resources used while the context names a part, each once, until taken.
    part_uses: Vec<ResourceUse>,
}

impl<'a> Recorder<'a> {
    pub fn new(
        gpu: &'a Gpu,
        cmd: vk::CommandBuffer,
        queue: &Queue,
        timer: Option<&'a mut FrameQueries>,
    ) -> Self {
        Recorder {
            gpu,
            cmd,
            queue: *queue,
            timer,
            context: ScopeTag::default(),
            part_uses: Vec::new(),
        }
    }

    /// The tag the next pass gets (its `pass` field is replaced by the pass's name).
    pub fn context(&self) -> ScopeTag {
        self.context
    }

    /// Set the tag context for the passes recorded from now on; returns the previous one.
    pub fn set_context(&mut self, context: ScopeTag) -> ScopeTag {
        std::mem::replace(&mut self.context, context)
    }

    /// Record `f`'s passes as step `step` (from 1) of a repeated pass.
    pub fn in_step<R>(&mut self, step: u32, f: impl FnOnce(&mut Self) -> R) -> R {
        let saved = self.set_context(ScopeTag {
            step: Some(step),
            ..self.context
        });
        let result = f(self);
        self.context = saved;
        result
    }

    /// Record `f`'s passes as part `part` of a method's independent parts.
    pub fn in_part<R>(&mut self, part: Part, f: impl FnOnce(&mut Self) -> R) -> R {
        let saved = self.set_context(ScopeTag {
            part: Some(part),
            ..self.context
        });
        let result = f(self);
        self.context = saved;
        result
    }

    /// Record `f`'s passes as rendering layer `layer` of a layered target.
    pub fn in_layer<R>(&mut self, layer: u32, f: impl FnOnce(&mut Self) -> R) -> R {
        let saved = self.set_context(ScopeTag {
            layer: Some(layer),
            ..self.context
        });
        let result = f(self);
        self.context = saved;
        result
    }

    pub fn gpu(&self) -> &Gpu {
        self.gpu
    }

    /// The tag of pass `pass` in the current context.
    fn tag(&self, pass: &'static str) -> ScopeTag {
        ScopeTag {
            pass,
            ..self.context
        }
    }

    pub(crate) fn begin_scope(&mut self, pass: &'static str) -> Option<u32> {
        let tag = self.tag(pass);
        if let Some(utils) = &self.gpu.shared.debug_utils
            && let Ok(label_name) = std::ffi::CString::new(tag.name())
        {
            let label = vk::DebugUtilsLabelEXT::default().label_name(&label_name);
            // SAFETY: recording into a command buffer in the recording state.
            unsafe { utils.cmd_begin_debug_utils_label(self.cmd, &label) };
        }
        let device = &self.gpu.shared.device;
        let family = self.queue.family;
        self.timer
            .as_mut()
            .and_then(|t| t.begin(device, self.cmd, family, tag))
    }

    pub(crate) fn end_scope(&mut self, scope: Option<u32>) {
        let device = &self.gpu.shared.device;
        if let (Some(t), Some(scope)) = (self.timer.as_mut(), scope) {
            t.end(device, self.cmd, scope);
        }
        if let Some(utils) = &self.gpu.shared.debug_utils {
            // SAFETY: closes the label opened in begin_scope on the same command buffer.
            unsafe { utils.cmd_end_debug_utils_label(self.cmd) };
        }
    }

    /// The resources used since the last call while the context named a part, each once, in
    /// the order first used (what the frame holds its parts to: `render::part_ledger`).
    pub fn take_part_uses(&mut self) -> Vec<ResourceUse> {
        std::mem::take(&mut self.part_uses)
    }

    /// Record the barriers that the accesses need, in one pipeline-barrier command.
    fn sync(&mut self, accesses: &[(Resource, Access)]) {
        let mut buffer_barriers = Vec::new();
        let mut image_barriers = Vec::new();
        // Reads before writes: where a pass reads and writes one resource through two bindings
        // (a texel read and a storage write, say), the read's barrier must wait for the
        // resource's last writer and the write's then covers the read; barriers in one command
        // do not chain, so the other order would leave the read waiting on this pass's write.
        let reads = accesses.iter().filter(|(_, access)| !access.writes());
        let writes = accesses.iter().filter(|(_, access)| access.writes());
        for (resource, access) in reads.chain(writes) {
            let relayout = match resource {
                Resource::Buffer(buffer) => {
                    let mut state = buffer.sync.get();
                    if let Some((ss, sa, ds, da, _)) =
                        transition(&mut state, *access, false, self.queue.stages)
                    {
                        buffer_barriers.push(
                            vk::BufferMemoryBarrier2::default()
                                .src_stage_mask(ss)
                                .src_access_mask(sa)
                                .dst_stage_mask(ds)
                                .dst_access_mask(da)
                                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                                .buffer(buffer.raw)
                                .offset(0)
                                .size(vk::WHOLE_SIZE),
                        );
                    }
                    buffer.sync.set(state);
                    false
                }
                Resource::Image(image) => {
                    let mut state = image.sync.get();
                    let barrier = transition(&mut state, *access, true, self.queue.stages);
                    if let Some((ss, sa, ds, da, old)) = barrier {
                        image_barriers.push(
                            vk::ImageMemoryBarrier2::default()
                                .src_stage_mask(ss)
                                .src_access_mask(sa)
                                .dst_stage_mask(ds)
                                .dst_access_mask(da)
                                .old_layout(old)
                                .new_layout(state.layout)
                                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                                .image(image.raw)
                                .subresource_range(image.subresource_range()),
                        );
                    }
                    image.sync.set(state);
                    barrier.is_some_and(|(.., old)| old != state.layout)
                }
            };
            if self.context.part.is_some() {
                let writes = access.writes() || relayout;
                let (key, name) = resource.key_and_name();
                match self.part_uses.iter_mut().find(|u| u.key == key) {
                    Some(used) => used.writes |= writes,
                    None => self.part_uses.push(ResourceUse {
                        key,
                        name: name.to_string(),
                        writes,
                    }),
                }
            }
        }
        if buffer_barriers.is_empty() && image_barriers.is_empty() {
            return;
        }
        let dependency = vk::DependencyInfo::default()
            .buffer_memory_barriers(&buffer_barriers)
            .image_memory_barriers(&image_barriers);
        // SAFETY: the barriers reference live resources; the command buffer is recording and
        // not inside a render pass instance.
        unsafe {
            self.gpu
                .shared
                .device
                .cmd_pipeline_barrier2(self.cmd, &dependency)
        };
    }

    /// Make everything written so far visible to every later command, whatever it touches.
    /// Used at the hand-over between independently recorded stages (e.g. before a readback).
    pub fn full_barrier(&mut self) {
        let barrier = vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE);
        let barriers = [barrier];
        let dependency = vk::DependencyInfo::default().memory_barriers(&barriers);
        // SAFETY: a plain memory barrier outside any render pass instance.
        unsafe {
            self.gpu
                .shared
                .device
                .cmd_pipeline_barrier2(self.cmd, &dependency)
        };
    }

    fn check_interface(
        &self,
        core: &PipelineCore,
        pass: &'static str,
        bindings: &[Binding],
        push: &dyn PushConstants,
    ) -> GpuResult<()> {
        let fail = |message: String| GpuError::Interface {
            pass: self.tag(pass).name(),
            message,
        };
        let interface = &core.interface;
        for &(number, kind) in &interface.bindings {
            match bindings.iter().find(|b| b.number() == number) {
                None => {
                    return Err(fail(format!(
                        "the shader declares {} at binding {number}, but the pass binds nothing there",
                        kind.name()
                    )));
                }
                Some(b) if b.kind() != kind => {
                    return Err(fail(format!(
                        "binding {number} is a {} in the shader but the pass binds a {}",
                        kind.name(),
                        b.kind().name()
                    )));
                }
                Some(_) => {}
            }
        }
        for b in bindings {
            let number = b.number();
            if !interface.bindings.iter().any(|(n, _)| *n == number) {
                return Err(fail(format!(
                    "the pass binds a {} at binding {number}, which the shader does not use",
                    b.kind().name()
                )));
            }
            if bindings.iter().filter(|o| o.number() == number).count() > 1 {
                return Err(fail(format!("binding {number} is bound twice")));
            }
            if let Binding::Texels { buffer, .. } = b
                && buffer.texel_view.is_none()
            {
                return Err(fail(format!(
                    "binding {number} reads buffer '{}' as texels, but it was made without a texel view",
                    buffer.name
                )));
            }
            if let Some(declared_write) = b.declared_write() {
                let writable = interface.writable.contains(&number);
                if writable && !declared_write {
                    return Err(fail(format!(
                        "binding {number} is declared read, but the shader may write it (declare it written, or mark it readonly in the shader)"
                    )));
                }
                if !writable && declared_write {
                    return Err(fail(format!(
                        "binding {number} is declared written, but the shader declares it readonly"
                    )));
                }
            }
        }
        match push::mismatch(
            push,
            interface.push_constant_size,
            &interface.push_constant_members,
        ) {
            Some(message) => Err(fail(message)),
            None => Ok(()),
        }
    }

    fn binding_accesses<'r>(
        bindings: &'r [Binding<'r>],
        graphics: bool,
    ) -> Vec<(Resource<'r>, Access)> {
        let (read, write, sampled) = if graphics {
            (
                Access::GraphicsRead,
                Access::GraphicsWrite,
                Access::GraphicsSampled,
            )
        } else {
            (
                Access::ComputeRead,
                Access::ComputeWrite,
                Access::ComputeSampled,
            )
        };
        bindings
            .iter()
            .map(|b| match b {
                Binding::StorageBuffer {
                    buffer, write: w, ..
                } => (Resource::Buffer(buffer), if *w { write } else { read }),
                Binding::UniformBuffer { buffer, .. } => (Resource::Buffer(buffer), read),
                Binding::StorageImage {
                    image, write: w, ..
                } => (Resource::Image(image), if *w { write } else { read }),
                Binding::SampledImage { image, .. } => (Resource::Image(image), sampled),
                Binding::Texels { buffer, .. } => (Resource::Buffer(buffer), sampled),
            })
            .collect()
    }

    fn bind(&self, core: &PipelineCore, bindings: &[Binding], push: &[u8]) {
        let mut buffer_infos = Vec::with_capacity(bindings.len());
        let mut image_infos = Vec::with_capacity(bindings.len());
        let mut texel_views = Vec::with_capacity(bindings.len());
        for b in bindings {
            match b {
                Binding::StorageBuffer { buffer, .. } | Binding::UniformBuffer { buffer, .. } => {
                    buffer_infos.push(vk::DescriptorBufferInfo {
                        buffer: buffer.raw,
                        offset: 0,
                        range: vk::WHOLE_SIZE,
                    })
                }
                Binding::StorageImage { image, .. } => image_infos.push(vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: image.view,
                    image_layout: vk::ImageLayout::GENERAL,
                }),
                Binding::SampledImage { image, sampler, .. } => {
                    image_infos.push(vk::DescriptorImageInfo {
                        sampler: *sampler,
                        image_view: image.view,
                        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    })
                }
                // check_interface refused a buffer without a view.
                Binding::Texels { buffer, .. } => {
                    texel_views.push(buffer.texel_view.unwrap_or_default())
                }
            }
        }
        let (mut next_buffer, mut next_image, mut next_texels) = (0, 0, 0);
        let writes: Vec<vk::WriteDescriptorSet> = bindings
            .iter()
            .map(|b| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_binding(b.number())
                    .descriptor_count(1);
                match b {
                    Binding::StorageBuffer { .. } | Binding::UniformBuffer { .. } => {
                        let ty = if matches!(b, Binding::UniformBuffer { .. }) {
                            vk::DescriptorType::UNIFORM_BUFFER
                        } else {
                            vk::DescriptorType::STORAGE_BUFFER
                        };
                        next_buffer += 1;
                        write
                            .descriptor_type(ty)
                            .buffer_info(std::slice::from_ref(&buffer_infos[next_buffer - 1]))
                    }
                    Binding::StorageImage { .. } | Binding::SampledImage { .. } => {
                        let ty = if matches!(b, Binding::StorageImage { .. }) {
                            vk::DescriptorType::STORAGE_IMAGE
                        } else {
                            vk::DescriptorType::COMBINED_IMAGE_SAMPLER
                        };
                        next_image += 1;
                        write
                            .descriptor_type(ty)
                            .image_info(std::slice::from_ref(&image_infos[next_image - 1]))
                    }
                    Binding::Texels { .. } => {
                        next_texels += 1;
                        write
                            .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
                            .texel_buffer_view(std::slice::from_ref(&texel_views[next_texels - 1]))
                    }
                }
            })
            .collect();
        let device = &self.gpu.shared.device;
        // SAFETY: pipeline, layout and descriptors are alive; the interface check guaranteed
        // that every write matches the set layout, and push fits the declared range.
        unsafe {
            device.cmd_bind_pipeline(self.cmd, core.bind_point, core.raw);
            if !writes.is_empty() {
                self.gpu.shared.push_descriptor.cmd_push_descriptor_set(
                    self.cmd,
                    core.bind_point,
                    core.layout,
                    0,
                    &writes,
                );
            }
            if !push.is_empty() {
                device.cmd_push_constants(self.cmd, core.layout, core.stages, 0, push);
            }
        }
    }

    /// Record a compute pass.
    pub fn compute(&mut self, pass: &ComputePass) -> GpuResult<()> {
        let core = &pass.pipeline.core;
        self.check_interface(core, pass.name, pass.bindings, pass.push)?;
        let local = pass.pipeline.local_size;
        let groups = [0, 1, 2].map(|i| pass.threads[i].div_ceil(local[i]));
        if groups.contains(&0) {
            return Ok(());
        }
        let scope = self.begin_scope(pass.name);
        self.sync(&Self::binding_accesses(pass.bindings, false));
        self.bind(core, pass.bindings, pass.push.bytes());
        // SAFETY: pipeline and descriptors are bound above; the group counts are non-zero.
        unsafe {
            self.gpu
                .shared
                .device
                .cmd_dispatch(self.cmd, groups[0], groups[1], groups[2])
        };
        self.end_scope(scope);
        Ok(())
    }

    /// Record a compute pass whose workgroup counts an earlier pass wrote: the
    /// `VkDispatchIndirectCommand` at byte `offset` of `args`, read behind a draw-indirect
    /// barrier. `pass.threads` must be `[0; 3]` (the count is the buffer's, not the host's).
    pub fn compute_indirect(
        &mut self,
        pass: &ComputePass,
        args: &Buffer,
        offset: u64,
    ) -> GpuResult<()> {
        let core = &pass.pipeline.core;
        self.check_interface(core, pass.name, pass.bindings, pass.push)?;
        if pass.threads != [0; 3] {
            return Err(GpuError::Interface {
                pass: pass.name.to_string(),
                message: "an indirect dispatch takes its workgroup counts from its buffer; threads must be [0, 0, 0]".into(),
            });
        }
        let scope = self.begin_scope(pass.name);
        let mut accesses = Self::binding_accesses(pass.bindings, false);
        accesses.push((Resource::Buffer(args), Access::IndirectRead));
        self.sync(&accesses);
        self.bind(core, pass.bindings, pass.push.bytes());
        // SAFETY: pipeline and descriptors are bound above; `args` is an indirect buffer whose
        // command an earlier pass wrote, made visible by the barrier `sync` recorded.
        unsafe {
            self.gpu
                .shared
                .device
                .cmd_dispatch_indirect(self.cmd, args.raw, offset)
        };
        self.end_scope(scope);
        Ok(())
    }

    /// Record a raster pass: clear the attachments, draw, end.
    pub fn raster(&mut self, pass: &RasterPass) -> GpuResult<()> {
        let core = &pass.pipeline.core;
        if pass.pipeline.depth.is_some() != pass.depth.is_some() {
            return Err(GpuError::Interface {
                pass: pass.name.to_string(),
                message: match pass.depth {
                    None => "its pipeline tests depth, but the pass has no depth attachment",
                    Some(_) => "the pass has a depth attachment its pipeline has no format for",
                }
                .into(),
            });
        }
        self.check_interface(core, pass.name, pass.bindings, pass.push)?;
        let extent = pass
            .color
            .first()
            .map(|(img, _, _)| img.extent)
            .or(pass.depth.map(|(img, _)| img.extent))
            .ok_or_else(|| GpuError::Interface {
                pass: pass.name.to_string(),
                message: "a raster pass needs at least one attachment".into(),
            })?;
        let scope = self.begin_scope(pass.name);
        let mut accesses = Self::binding_accesses(pass.bindings, true);
        for (image, _, _) in pass.color {
            accesses.push((Resource::Image(image), Access::ColorAttachment));
        }
        // A pass that only tests against its depth attachment reads it as an earlier pass left
        // it; one that keeps the nearest fragment clears it unless it keeps its contents.
        let tests_only = matches!(pass.pipeline.depth, Some(Depth::Covered(_)));
        let depth_access = if tests_only {
            Access::DepthTest
        } else {
            Access::DepthAttachment
        };
        if let Some((image, _)) = pass.depth {
            accesses.push((Resource::Image(image), depth_access));
        }
        if let Draw::Indirect { buffer, .. } = pass.draw {
            accesses.push((Resource::Buffer(buffer), Access::IndirectRead));
        }
        self.sync(&accesses);

        let load_op = if pass.keep_contents {
            vk::AttachmentLoadOp::LOAD
        } else {
            vk::AttachmentLoadOp::CLEAR
        };
        let color_attachments: Vec<vk::RenderingAttachmentInfo> = pass
            .color
            .iter()
            .map(|(image, layer, clear)| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(layer_view(image, *layer))
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(load_op)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue { float32: *clear },
                    })
            })
            .collect();
        let (depth_layout, depth_load, depth_store) = if tests_only {
            (
                vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
                vk::AttachmentLoadOp::LOAD,
                vk::AttachmentStoreOp::NONE,
            )
        } else {
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                load_op,
                vk::AttachmentStoreOp::STORE,
            )
        };
        let depth_attachment = pass.depth.map(|(image, layer)| {
            vk::RenderingAttachmentInfo::default()
                .image_view(layer_view(image, layer))
                .image_layout(depth_layout)
                .load_op(depth_load)
                .store_op(depth_store)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: 1.0,
                        stencil: 0,
                    },
                })
        });
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: extent.width,
                height: extent.height,
            },
        };
        let mut rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachments);
        if let Some(depth) = depth_attachment.as_ref() {
            rendering = rendering.depth_attachment(depth);
        }
        let device = &self.gpu.shared.device;
        // SAFETY: attachments were transitioned to their attachment layouts by `sync`.
        unsafe { device.cmd_begin_rendering(self.cmd, &rendering) };
        self.bind(core, pass.bindings, pass.push.bytes());
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: inside the rendering instance begun above, with the pipeline bound.
        unsafe {
            device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            device.cmd_set_scissor(self.cmd, 0, &[area]);
            match pass.draw {
                Draw::Vertices(0) => {}
                Draw::Vertices(count) => device.cmd_draw(self.cmd, count, 1, 0, 0),
                Draw::Indirect { buffer, offset } => {
                    device.cmd_draw_indirect(self.cmd, buffer.raw, offset, 1, 0)
                }
            }
            device.cmd_end_rendering(self.cmd);
        }
        self.end_scope(scope);
        Ok(())
    }

    /// Copy `size` bytes from the start of `src` to the start of `dst`.
    pub fn copy_buffer(&mut self, name: &'static str, src: &Buffer, dst: &Buffer, size: u64) {
        self.copy_buffers(name, &[(src, dst, size)]);
    }

    /// Each copy `(src, dst, size)`: `size` bytes from the start of `src` to the start of
    /// `dst`, as one pass (one barrier and one timestamp scope for all: on lavapipe each pass
    /// costs tens of microseconds however little it moves). No buffer may be both a source and
    /// a destination, nor a destination twice.
    pub fn copy_buffers(&mut self, name: &'static str, copies: &[(&Buffer, &Buffer, u64)]) {
        debug_assert!(
            copies
                .iter()
                .all(|(_, dst, _)| copies.iter().all(|(src, _, _)| src.raw != dst.raw)),
            "{name}: a buffer is both copied from and to"
        );
        debug_assert!(
            all_distinct(copies.iter().map(|(_, dst, _)| dst.raw)),
            "{name}: a buffer is copied to twice"
        );
        let scope = self.begin_scope(name);
        let accesses: Vec<(Resource, Access)> = copies
            .iter()
            .flat_map(|&(src, dst, _)| {
                [
                    (Resource::Buffer(src), Access::TransferRead),
                    (Resource::Buffer(dst), Access::TransferWrite),
                ]
            })
            .collect();
        self.sync(&accesses);
        for &(src, dst, size) in copies.iter().filter(|(_, _, size)| *size > 0) {
            let region = vk::BufferCopy {
                src_offset: 0,
                dst_offset: 0,
                size,
            };
            // SAFETY: both buffers are alive and at least `size` bytes long.
            unsafe {
                self.gpu
                    .shared
                    .device
                    .cmd_copy_buffer(self.cmd, src.raw, dst.raw, &[region])
            };
        }
        self.end_scope(scope);
    }

    /// Fill a buffer with a repeated 32-bit value (0 clears it).
    pub fn fill_buffer(&mut self, name: &'static str, buffer: &Buffer, value: u32) {
        self.fill_buffers(name, &[(buffer, value)]);
    }

    /// Fill each buffer (each once) with its repeated 32-bit value, as one pass (one barrier
    /// and one timestamp scope for all).
    pub fn fill_buffers(&mut self, name: &'static str, fills: &[(&Buffer, u32)]) {
        debug_assert!(
            all_distinct(fills.iter().map(|(buffer, _)| buffer.raw)),
            "{name}: a buffer is filled twice"
        );
        let scope = self.begin_scope(name);
        let accesses: Vec<(Resource, Access)> = fills
            .iter()
            .map(|&(buffer, _)| (Resource::Buffer(buffer), Access::TransferWrite))
            .collect();
        self.sync(&accesses);
        for &(buffer, value) in fills {
            // SAFETY: the buffer is alive and was created with TRANSFER_DST.
            unsafe {
                self.gpu.shared.device.cmd_fill_buffer(
                    self.cmd,
                    buffer.raw,
                    0,
                    vk::WHOLE_SIZE,
                    value,
                )
            };
        }
        self.end_scope(scope);
    }

    /// Overwrite the start of a buffer with `data` from the command buffer (a multiple of 4
    /// bytes), ordered with the passes around it like any transfer.
    pub fn update_buffer(&mut self, name: &'static str, buffer: &Buffer, data: &[u8]) {
        self.update_buffer_at(name, buffer, 0, data);
    }

    /// Write `data` into `buffer` from byte `offset` (both multiples of 4), in the command
    /// stream (vkCmdUpdateBuffer, 65536 bytes at a time).
    pub fn update_buffer_at(
        &mut self,
        name: &'static str,
        buffer: &Buffer,
        offset: u64,
        data: &[u8],
    ) {
        self.update_buffer_runs(name, buffer, &[(offset, data.to_vec())]);
    }

    /// Write each run `(offset, data)` into `buffer` (offsets and lengths multiples of 4), in
    /// the command stream, as one pass (one barrier, one timestamp scope).
    pub fn update_buffer_runs(
        &mut self,
        name: &'static str,
        buffer: &Buffer,
        runs: &[(u64, Vec<u8>)],
    ) {
        if runs.iter().all(|(_, data)| data.is_empty()) {
            return;
        }
        let scope = self.begin_scope(name);
        self.sync(&[(Resource::Buffer(buffer), Access::TransferWrite)]);
        const MAX_UPDATE: usize = 65536;
        for (offset, data) in runs {
            for (k, chunk) in data.chunks(MAX_UPDATE).enumerate() {
                let at = offset + (k * MAX_UPDATE) as u64;
                // SAFETY: the buffer is alive and has TRANSFER_DST; the caller keeps the
                // offsets and the data's lengths multiples of 4 and within the buffer.
                unsafe {
                    self.gpu
                        .shared
                        .device
                        .cmd_update_buffer(self.cmd, buffer.raw, at, chunk)
                };
            }
        }
        self.end_scope(scope);
    }

    /// Clear a colour image to `colour`.
    pub fn clear_image(&mut self, name: &'static str, image: &Image, colour: [f32; 4]) {
        let scope = self.begin_scope(name);
        self.sync(&[(Resource::Image(image), Access::TransferWrite)]);
        let value = vk::ClearColorValue { float32: colour };
        // SAFETY: the image is alive, has TRANSFER_DST and is in TRANSFER_DST_OPTIMAL after
        // `sync`.
        unsafe {
            self.gpu.shared.device.cmd_clear_color_image(
                self.cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &value,
                &[image.subresource_range()],
            )
        };
        self.end_scope(scope);
    }

    /// Copy a rectangle of `src` (x, y, width, height) into a rectangle of `dst`, scaling with
    /// linear filtering when the sizes differ (a negative width or height flips). Rectangles
    /// of one positive size between images of one format are copied texel for texel
    /// (`vkCmdCopyImage`: on lavapipe a memory copy, where a blit draws).
    pub fn blit(
        &mut self,
        name: &'static str,
        src: &Image,
        from: [i32; 4],
        dst: &Image,
        to: [i32; 4],
    ) {
        let scope = self.begin_scope(name);
        self.sync(&[
            (Resource::Image(src), Access::TransferRead),
            (Resource::Image(dst), Access::TransferWrite),
        ]);
        let region = blit_region(from, to);
        let copy = vk::ImageCopy {
            src_subresource: region.src_subresource,
            src_offset: region.src_offsets[0],
            dst_subresource: region.dst_subresource,
            dst_offset: region.dst_offsets[0],
            extent: vk::Extent3D {
                width: from[2] as u32,
                height: from[3] as u32,
                depth: 1,
            },
        };
        let (device, cmd) = (&self.gpu.shared.device, self.cmd);
        let (src_layout, dst_layout) = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        // SAFETY: both images are alive with TRANSFER_SRC / TRANSFER_DST usage and in the
        // layouts `sync` put them in; the copy only between images of one format.
        unsafe {
            if from[2..] == to[2..] && from[2] > 0 && from[3] > 0 && src.format == dst.format {
                device.cmd_copy_image(cmd, src.raw, src_layout, dst.raw, dst_layout, &[copy]);
            } else {
                let filter = vk::Filter::LINEAR;
                device.cmd_blit_image(
                    cmd,
                    src.raw,
                    src_layout,
                    dst.raw,
                    dst_layout,
                    &[region],
                    filter,
                );
            }
        };
        self.end_scope(scope);
    }

    /// Copy all of `src` onto a swapchain image `target` of the same size and leave the target
    /// ready to present. `target`'s previous contents are discarded; the submission must wait
    /// for its acquisition at the BLIT stage.
    pub fn blit_to_swapchain(&mut self, src: &Image, target: vk::Image) {
        let scope = self.begin_scope("present blit");
        self.sync(&[(Resource::Image(src), Access::TransferRead)]);
        let colour = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let barrier = vk::ImageMemoryBarrier2::default()
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(target)
            .subresource_range(colour);
        let to_transfer = barrier
            .src_stage_mask(vk::PipelineStageFlags2::BLIT)
            .dst_stage_mask(vk::PipelineStageFlags2::BLIT)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL);
        let to_present = barrier
            .src_stage_mask(vk::PipelineStageFlags2::BLIT)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .new_layout(vk::ImageLayout::PRESENT_SRC_KHR);
        let (w, h) = (src.width() as i32, src.height() as i32);
        let region = blit_region([0, 0, w, h], [0, 0, w, h]);
        let device = &self.gpu.shared.device;
        // SAFETY: `target` is an acquired swapchain image (TRANSFER_DST usage) whose
        // acquisition the submission waits for at the BLIT stage, which the first barrier
        // chains to; `src` is in TRANSFER_SRC_OPTIMAL after `sync`.
        unsafe {
            let barriers = [to_transfer];
            device.cmd_pipeline_barrier2(
                self.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&barriers),
            );
            device.cmd_blit_image(
                self.cmd,
                src.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::NEAREST,
            );
            let barriers = [to_present];
            device.cmd_pipeline_barrier2(
                self.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&barriers),
            );
        }
        self.end_scope(scope);
    }

    /// Copy every layer of an image into a buffer, tightly packed, layer after layer.
    pub fn copy_image_to_buffer(&mut self, name: &'static str, image: &Image, buffer: &Buffer) {
        let scope = self.begin_scope(name);
        self.sync(&[
            (Resource::Image(image), Access::TransferRead),
            (Resource::Buffer(buffer), Access::TransferWrite),
        ]);
        let region = whole_image_copy(image);
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL after `sync`; the buffer is large enough
        // for every layer (callers size it from the image).
        unsafe {
            self.gpu.shared.device.cmd_copy_image_to_buffer(
                self.cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.raw,
                &[region],
            )
        };
        self.end_scope(scope);
    }

    /// Copy a tightly packed buffer into the box of `image` that starts at texel `offset` and
    /// spans `extent` texels (layer 0), leaving the rest of the image as it was.
    pub fn copy_buffer_to_box(
        &mut self,
        name: &'static str,
        buffer: &Buffer,
        image: &Image,
        offset: [i32; 3],
        extent: [u32; 3],
    ) {
        let scope = self.begin_scope(name);
        self.sync(&[
            (Resource::Buffer(buffer), Access::TransferRead),
            (Resource::Image(image), Access::TransferWrite),
        ]);
        let region = vk::BufferImageCopy {
            image_offset: vk::Offset3D {
                x: offset[0],
                y: offset[1],
                z: offset[2],
            },
            image_extent: vk::Extent3D {
                width: extent[0],
                height: extent[1],
                depth: extent[2],
            },
            ..whole_image_copy(image)
        };
        // SAFETY: the image is in TRANSFER_DST_OPTIMAL after `sync` (a layout change keeps its
        // contents: the old layout is the tracked one); callers size the buffer to hold every
        // texel of the box.
        unsafe {
            self.gpu.shared.device.cmd_copy_buffer_to_image(
                self.cmd,
                buffer.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
        self.end_scope(scope);
    }

    /// Make a buffer's device writes visible to the host once the submission's fence signals.
    pub fn host_read(&mut self, buffer: &Buffer) {
        self.sync(&[(Resource::Buffer(buffer), Access::HostRead)]);
    }
}

/// A copy of every layer of `image` from or to a tightly packed buffer.
fn whole_image_copy(image: &Image) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset: 0,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: image.aspect,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: image.layers,
        },
        image_offset: vk::Offset3D { x: 0, y: 0, z: 0 },
        image_extent: image.extent,
    }
}

/// A blit of colour layer 0 from rectangle `from` to `to` (x, y, width, height).
fn blit_region(from: [i32; 4], to: [i32; 4]) -> vk::ImageBlit {
    let corners = |r: [i32; 4]| {
        [
            vk::Offset3D {
                x: r[0],
                y: r[1],
                z: 0,
            },
            vk::Offset3D {
                x: r[0] + r[2],
                y: r[1] + r[3],
                z: 1,
            },
        ]
    };
    let layer = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    vk::ImageBlit {
        src_subresource: layer,
        src_offsets: corners(from),
        dst_subresource: layer,
        dst_offsets: corners(to),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a graphics and compute family runs, and a dedicated async compute family.
    const GRAPHICS_QUEUE: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(u64::MAX);

    fn compute_queue() -> vk::PipelineStageFlags2 {
        queue_stages(vk::QueueFlags::COMPUTE | vk::QueueFlags::TRANSFER)
    }

    type Barrier = (
        vk::PipelineStageFlags2,
        vk::AccessFlags2,
        vk::PipelineStageFlags2,
        vk::AccessFlags2,
        vk::ImageLayout,
    );

    /// The barrier `access` needs on the graphics queue; fails the test if it needs none.
    fn barrier(state: &mut SyncState, access: Access, is_image: bool) -> Barrier {
        barrier_on(state, access, is_image, GRAPHICS_QUEUE)
    }

    /// The barrier `access` needs on a queue running `queue`; fails the test if it needs none.
    fn barrier_on(
        state: &mut SyncState,
        access: Access,
        is_image: bool,
        queue: vk::PipelineStageFlags2,
    ) -> Barrier {
        match transition(state, access, is_image, queue) {
            Some(b) => b,
            None => panic!("{access:?} needs a barrier"),
        }
    }

    #[test]
    fn read_after_write_needs_one_barrier_then_none() {
        let mut s = SyncState::default();
        let first = barrier(&mut s, Access::ComputeWrite, false);
        assert!(first.0.is_empty(), "a fresh resource waits on nothing");
        let raw = barrier(&mut s, Access::ComputeRead, false);
        assert_eq!(raw.0, vk::PipelineStageFlags2::COMPUTE_SHADER);
        assert!(raw.1.contains(vk::AccessFlags2::SHADER_STORAGE_WRITE));
        assert!(transition(&mut s, Access::ComputeRead, false, GRAPHICS_QUEUE).is_none());
    }

    #[test]
    fn write_after_read_waits_on_the_readers() {
        let mut s = SyncState::default();
        transition(&mut s, Access::TransferWrite, false, GRAPHICS_QUEUE);
        transition(&mut s, Access::GraphicsRead, false, GRAPHICS_QUEUE);
        let war = barrier(&mut s, Access::ComputeWrite, false);
        assert!(war.0.contains(vk::PipelineStageFlags2::VERTEX_SHADER));
        assert!(war.0.contains(vk::PipelineStageFlags2::ALL_TRANSFER));
    }

    #[test]
    fn image_layout_changes_always_get_a_barrier() {
        let mut s = SyncState::default();
        let t = barrier(&mut s, Access::ColorAttachment, true);
        assert_eq!(t.4, vk::ImageLayout::UNDEFINED);
        assert_eq!(s.layout, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        let t = barrier(&mut s, Access::ComputeRead, true);
        assert_eq!(t.4, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        assert_eq!(s.layout, vk::ImageLayout::GENERAL);
        // A second read stage after the transition still waits for the transition.
        let t = barrier(&mut s, Access::TransferRead, true);
        assert_eq!(t.4, vk::ImageLayout::GENERAL);
    }

    #[test]
    fn a_depth_test_reads_the_depth_written_before_in_a_read_only_layout() {
        use vk::{AccessFlags2 as A, ImageLayout as L};
        let mut s = SyncState::default();
        transition(&mut s, Access::DepthAttachment, true, GRAPHICS_QUEUE);
        let t = barrier(&mut s, Access::DepthTest, true);
        assert!(
            t.1.contains(A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            "waits on the write"
        );
        assert_eq!(t.3, A::DEPTH_STENCIL_ATTACHMENT_READ, "and only reads");
        assert_eq!(
            (t.4, s.layout),
            (L::DEPTH_ATTACHMENT_OPTIMAL, L::DEPTH_READ_ONLY_OPTIMAL)
        );
        // Two passes testing one after the other need nothing between them; the next frame's
        // write waits on the tests.
        assert!(transition(&mut s, Access::DepthTest, true, GRAPHICS_QUEUE).is_none());
        let t = barrier(&mut s, Access::DepthAttachment, true);
        assert_eq!(t.4, L::DEPTH_READ_ONLY_OPTIMAL);
    }

    #[test]
    fn a_new_reader_stage_waits_on_the_last_write() {
        let mut s = SyncState::default();
        transition(&mut s, Access::ComputeWrite, false, GRAPHICS_QUEUE);
        transition(&mut s, Access::ComputeRead, false, GRAPHICS_QUEUE);
        let t = barrier(&mut s, Access::TransferRead, false);
        assert_eq!(t.0, vk::PipelineStageFlags2::COMPUTE_SHADER);
        assert!(transition(&mut s, Access::TransferRead, false, GRAPHICS_QUEUE).is_none());
    }

    #[test]
    fn a_compute_family_runs_no_graphics_stage() {
        use vk::PipelineStageFlags2 as S;
        let all = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE | vk::QueueFlags::TRANSFER;
        assert_eq!(queue_stages(all), GRAPHICS_QUEUE);
        let compute = compute_queue();
        for stage in [
            S::COMPUTE_SHADER,
            S::ALL_TRANSFER,
            S::HOST,
            S::DRAW_INDIRECT,
        ] {
            assert!(compute.contains(stage), "{stage:?}");
        }
        for stage in [
            S::VERTEX_SHADER,
            S::FRAGMENT_SHADER,
            S::COLOR_ATTACHMENT_OUTPUT,
            S::EARLY_FRAGMENT_TESTS,
            S::LATE_FRAGMENT_TESTS,
        ] {
            assert!(!compute.intersects(stage), "{stage:?}");
        }
    }

    #[test]
    fn a_compute_queue_barrier_names_only_its_own_stages() {
        use vk::PipelineStageFlags2 as S;
        // Written and read by compute on this queue, read by a fragment shader on the graphics
        // queue, then written here again: the write waits on the compute read only.
        let mut s = SyncState::default();
        transition(&mut s, Access::ComputeWrite, false, compute_queue());
        transition(&mut s, Access::ComputeRead, false, compute_queue());
        transition(&mut s, Access::GraphicsSampled, false, GRAPHICS_QUEUE);
        let war = barrier_on(&mut s, Access::ComputeWrite, false, compute_queue());
        assert_eq!(war.0, S::COMPUTE_SHADER);
        assert!(war.1.contains(vk::AccessFlags2::SHADER_STORAGE_WRITE));

        // Written by a fragment shader on the graphics queue: a compute read here has nothing of
        // this queue's to wait on (the semaphore orders it), a compute write waits on no stage
        // and makes no access available.
        let mut s = SyncState::default();
        transition(&mut s, Access::GraphicsWrite, false, GRAPHICS_QUEUE);
        assert!(transition(&mut s, Access::ComputeRead, false, compute_queue()).is_none());
        let mut s = SyncState::default();
        transition(&mut s, Access::ColorAttachment, true, GRAPHICS_QUEUE);
        let waw = barrier_on(&mut s, Access::ComputeWrite, true, compute_queue());
        assert_eq!((waw.0, waw.1), (S::ALL_COMMANDS, vk::AccessFlags2::NONE));
        assert_eq!(
            waw.4,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            "the layout still changes"
        );

        // The graphics queue runs compute too: there a compute write is waited on.
        let raw = barrier(&mut s, Access::GraphicsSampled, true);
        assert_eq!(raw.0, S::COMPUTE_SHADER);
    }
}
