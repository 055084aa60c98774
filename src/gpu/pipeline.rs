//! Compute and graphics pipelines from the embedded SPIR-V. The descriptor-set layout (push
//! descriptors, set 0) and push-constant range come from the SPIR-V's own interface, which the
//! pass recorder later checks every pass's bindings against.

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::context::{DescriptorLimits, DeviceShared, Gpu};
use super::reflect::{DescriptorKind, ShaderInterface, reflect};
use super::{GpuError, GpuResult, vk_err};

const ENTRY: &CStr = c"main";

/// Specialization-constant values (all 4-byte: u32, i32 or f32 bits).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Specialization {
    entries: Vec<(u32, u32)>,
}

impl Specialization {
    pub fn new() -> Self {
        Self::default()
    }
    pub fn with_u32(mut self, id: u32, value: u32) -> Self {
        self.entries.retain(|(i, _)| *i != id);
        self.entries.push((id, value));
        self
    }
    pub fn with_f32(self, id: u32, value: f32) -> Self {
        self.with_u32(id, value.to_bits())
    }
    /// The value given to constant `id`, if any.
    pub(crate) fn value(&self, id: u32) -> Option<u32> {
        self.entries.iter().find(|(i, _)| *i == id).map(|e| e.1)
    }
    /// The map entries and data of a `vk::SpecializationInfo`, four bytes per constant.
    fn map(&self) -> (Vec<vk::SpecializationMapEntry>, Vec<u8>) {
        let entries = self
            .entries
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                constant_id: id,
                offset: (i * 4) as u32,
                size: 4,
            })
            .collect();
        let data = self
            .entries
            .iter()
            .flat_map(|&(_, v)| v.to_ne_bytes())
            .collect();
        (entries, data)
    }
}

/// What every pipeline has: its layout, its interface, and the device to destroy it with.
pub struct PipelineCore {
    shared: Arc<DeviceShared>,
    pub name: String,
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pub interface: ShaderInterface,
    pub bind_point: vk::PipelineBindPoint,
    pub stages: vk::ShaderStageFlags,
}

impl Drop for PipelineCore {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no pending command buffer uses the pipeline.
        unsafe {
            self.shared.device.destroy_pipeline(self.raw, None);
            self.shared
                .device
                .destroy_pipeline_layout(self.layout, None);
            self.shared
                .device
                .destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

pub struct ComputePipeline {
    pub core: PipelineCore,
    /// Threads per workgroup, after specialization.
    pub local_size: [u32; 3],
}

pub struct RasterPipeline {
    pub core: PipelineCore,
    /// Its depth attachment and test, if it has one.
    pub depth: Option<Depth>,
}

/// A raster pipeline's depth attachment (its format) and how its fragments test against it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depth {
    /// Keep the nearest fragment: test LESS and write (a pass clears the attachment to 1 unless
    /// it keeps its contents).
    Nearest(vk::Format),
    /// Shade only the pixels a surface covers in a depth buffer drawn before: the fragments of a
    /// triangle at the far plane (common/fullscreen.vert) pass GREATER where the attachment
    /// holds a nearer depth, and fail where it holds the clear value 1 (background), so
    /// lavapipe skips the batches of background pixels before shading them. The attachment is
    /// read as it is (loaded, read only, not written).
    Covered(vk::Format),
}

impl Depth {
    fn format(self) -> vk::Format {
        match self {
            Depth::Nearest(format) | Depth::Covered(format) => format,
        }
    }
}

#[derive(Clone, Debug)]
pub struct RasterPipelineDesc<'a> {
    pub name: &'a str,
    pub vertex: &'a [u8],
    pub fragment: Option<&'a [u8]>,
    pub color_formats: &'a [vk::Format],
    pub depth: Option<Depth>,
    /// Constant and slope-scaled depth bias (for shadow maps).
    pub depth_bias: Option<(f32, f32)>,
    /// Add the fragments' outputs to the attachments (one plus one) instead of replacing them.
    pub additive_blend: bool,
    /// Rasterise every pixel a triangle touches (overestimating conservative rasterisation,
    /// a quarter pixel beyond the square where the device allows; only on a device with
    /// VK_EXT_conservative_rasterization, see `DeviceInfo`).
    pub conservative: bool,
    /// Specialisation constants of both stages.
    pub specialization: &'a Specialization,
}

fn descriptor_type(kind: DescriptorKind) -> vk::DescriptorType {
    match kind {
        DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
        DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
        DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
        DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
        DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
        DescriptorKind::UniformTexelBuffer => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        DescriptorKind::StorageTexelBuffer => vk::DescriptorType::STORAGE_TEXEL_BUFFER,
    }
}

fn words(name: &str, bytes: &[u8]) -> GpuResult<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes)).map_err(|e| GpuError::Interface {
        pass: name.to_string(),
        message: format!("embedded SPIR-V is unreadable: {e}"),
    })
}

fn reflect_named(name: &str, words: &[u32]) -> GpuResult<ShaderInterface> {
    reflect(words).map_err(|message| GpuError::Interface {
        pass: name.to_string(),
        message,
    })
}

struct ShaderModule<'a> {
    shared: &'a DeviceShared,
    raw: vk::ShaderModule,
}

impl<'a> ShaderModule<'a> {
    fn new(shared: &'a DeviceShared, name: &str, words: &[u32]) -> GpuResult<Self> {
        let info = vk::ShaderModuleCreateInfo::default().code(words);
        // SAFETY: `words` is SPIR-V produced by shaderc at build time.
        let raw = unsafe { shared.device.create_shader_module(&info, None) }
            .map_err(vk_err(&format!("creating the shader module of {name}")))?;
        Ok(ShaderModule { shared, raw })
    }
}

impl Drop for ShaderModule<'_> {
    fn drop(&mut self) {
        // SAFETY: modules may be destroyed once the pipelines using them are created.
        unsafe { self.shared.device.destroy_shader_module(self.raw, None) };
    }
}

/// Refuse a pipeline whose shader stage binds more descriptors of a kind than the device allows
/// per stage, or more bindings than a push-descriptor set holds.
fn check_descriptor_limits(
    limits: &DescriptorLimits,
    name: &str,
    interface: &ShaderInterface,
) -> GpuResult<()> {
    let count = |kinds: &[DescriptorKind]| {
        interface
            .bindings
            .iter()
            .filter(|(_, kind)| kinds.contains(kind))
            .count() as u32
    };
    use DescriptorKind as K;
    let checks = [
        (
            "storage buffers",
            count(&[K::StorageBuffer]),
            limits.storage_buffers,
        ),
        (
            "uniform buffers",
            count(&[K::UniformBuffer]),
            limits.uniform_buffers,
        ),
        (
            "sampled images and uniform texel buffers",
            count(&[
                K::SampledImage,
                K::CombinedImageSampler,
                K::UniformTexelBuffer,
            ]),
            limits.sampled_images,
        ),
        (
            "storage images and storage texel buffers",
            count(&[K::StorageImage, K::StorageTexelBuffer]),
            limits.storage_images,
        ),
        (
            "samplers",
            count(&[K::Sampler, K::CombinedImageSampler]),
            limits.samplers,
        ),
        (
            "push-descriptor bindings",
            interface.bindings.len() as u32,
            limits.push_descriptors,
        ),
    ];
    match checks.into_iter().find(|(_, used, limit)| used > limit) {
        Some((what, used, limit)) => Err(GpuError::Interface {
            pass: name.to_string(),
            message: format!("binds {used} {what}; the device allows {limit}"),
        }),
        None => Ok(()),
    }
}

fn create_layouts(
    gpu: &Gpu,
    name: &str,
    interface: &ShaderInterface,
    stages: vk::ShaderStageFlags,
) -> GpuResult<(vk::DescriptorSetLayout, vk::PipelineLayout)> {
    check_descriptor_limits(&gpu.info.descriptor_limits, name, interface)?;
    let device = &gpu.shared.device;
    let bindings: Vec<vk::DescriptorSetLayoutBinding> = interface
        .bindings
        .iter()
        .map(|&(binding, kind)| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(descriptor_type(kind))
                .descriptor_count(1)
                .stage_flags(stages)
        })
        .collect();
    let set_info = vk::DescriptorSetLayoutCreateInfo::default()
        .flags(vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR)
        .bindings(&bindings);
    // SAFETY: valid create info on a device with VK_KHR_push_descriptor enabled.
    let set_layout = unsafe { device.create_descriptor_set_layout(&set_info, None) }
        .map_err(vk_err(&format!("creating the descriptor layout of {name}")))?;
    if interface.push_constant_size > gpu.info.max_push_constants_size {
        // SAFETY: just created, unused.
        unsafe { device.destroy_descriptor_set_layout(set_layout, None) };
        return Err(GpuError::Interface {
            pass: name.to_string(),
            message: format!(
                "push constants of {} bytes exceed the device limit of {}",
                interface.push_constant_size, gpu.info.max_push_constants_size
            ),
        });
    }
    let ranges = [vk::PushConstantRange {
        stage_flags: stages,
        offset: 0,
        size: interface.push_constant_size,
    }];
    let set_layouts = [set_layout];
    let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
    if interface.push_constant_size > 0 {
        layout_info = layout_info.push_constant_ranges(&ranges);
    }
    // SAFETY: valid create info referencing the set layout above.
    match unsafe { device.create_pipeline_layout(&layout_info, None) } {
        Ok(layout) => Ok((set_layout, layout)),
        Err(e) => {
            // SAFETY: just created, unused.
            unsafe { device.destroy_descriptor_set_layout(set_layout, None) };
            Err(GpuError::Vulkan {
                what: format!("creating the pipeline layout of {name}"),
                result: e,
            })
        }
    }
}

impl ComputePipeline {
    pub fn new(gpu: &Gpu, name: &str, spirv: &[u8], spec: &Specialization) -> GpuResult<Self> {
        let code = words(name, spirv)?;
        let interface = reflect_named(name, &code)?;
        let mut local_size = interface.local_size.ok_or_else(|| GpuError::Interface {
            pass: name.to_string(),
            message: "compute shader declares no workgroup size".into(),
        })?;
        for (axis, id) in interface.local_size_spec_ids.iter().enumerate() {
            if let Some(value) = id.and_then(|id| spec.value(id)) {
                local_size[axis] = value;
            }
        }
        let invocations = local_size.iter().product::<u32>();
        if invocations == 0 || invocations > gpu.info.max_workgroup_invocations {
            return Err(GpuError::Interface {
                pass: name.to_string(),
                message: format!(
                    "workgroup {local_size:?} has {invocations} invocations; the device allows 1..={}",
                    gpu.info.max_workgroup_invocations
                ),
            });
        }
        let stages = vk::ShaderStageFlags::COMPUTE;
        let (set_layout, layout) = create_layouts(gpu, name, &interface, stages)?;
        // From here, dropping `core` releases the layouts on any error path.
        let mut core = PipelineCore {
            shared: gpu.shared.clone(),
            name: name.to_string(),
            raw: vk::Pipeline::null(),
            layout,
            set_layout,
            interface,
            bind_point: vk::PipelineBindPoint::COMPUTE,
            stages,
        };
        let module = ShaderModule::new(&gpu.shared, name, &code)?;
        let (map_entries, data) = spec.map();
        let spec_info = vk::SpecializationInfo::default()
            .map_entries(&map_entries)
            .data(&data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw)
            .name(ENTRY)
            .specialization_info(&spec_info);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout);
        // SAFETY: valid create info; module and layout are alive for the call.
        let pipelines = unsafe {
            gpu.shared
                .device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, e)| GpuError::Vulkan {
            what: format!("creating compute pipeline {name}"),
            result: e,
        })?;
        core.raw = pipelines[0];
        gpu.shared.set_name(core.raw, name);
        Ok(ComputePipeline { core, local_size })
    }
}

impl RasterPipeline {
    pub fn new(gpu: &Gpu, desc: &RasterPipelineDesc) -> GpuResult<Self> {
        let name = desc.name;
        let vertex_code = words(name, desc.vertex)?;
        let mut interface = reflect_named(name, &vertex_code)?;
        let fragment_code = desc.fragment.map(|f| words(name, f)).transpose()?;
        if let Some(code) = &fragment_code {
            let fragment = reflect_named(name, code)?;
            interface
                .merge(&fragment)
                .map_err(|message| GpuError::Interface {
                    pass: name.to_string(),
                    message,
                })?;
        }
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let (set_layout, layout) = create_layouts(gpu, name, &interface, stages)?;
        let mut core = PipelineCore {
            shared: gpu.shared.clone(),
            name: name.to_string(),
            raw: vk::Pipeline::null(),
            layout,
            set_layout,
            interface,
            bind_point: vk::PipelineBindPoint::GRAPHICS,
            stages,
        };
        let vertex = ShaderModule::new(&gpu.shared, name, &vertex_code)?;
        let fragment = fragment_code
            .as_ref()
            .map(|code| ShaderModule::new(&gpu.shared, name, code))
            .transpose()?;
        let (map_entries, data) = desc.specialization.map();
        let spec_info = vk::SpecializationInfo::default()
            .map_entries(&map_entries)
            .data(&data);
        let mut stage_infos = vec![
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vertex.raw)
                .name(ENTRY)
                .specialization_info(&spec_info),
        ];
        if let Some(f) = &fragment {
            stage_infos.push(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::FRAGMENT)
                    .module(f.raw)
                    .name(ENTRY)
                    .specialization_info(&spec_info),
            );
        }
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let (bias_on, bias_constant, bias_slope) = match desc.depth_bias {
            Some((c, s)) => (true, c, s),
            None => (false, 0.0, 0.0),
        };
        // A quarter pixel beyond the square (where the device allows it), so a vertex the
        // rasteriser snaps inward still reaches the pixel it touched.
        let extra = gpu
            .info
            .conservative_rasterization
            .map_or(0.0, |c| c.max_extra_overestimation.min(0.25));
        let mut conservative = vk::PipelineRasterizationConservativeStateCreateInfoEXT::default()
            .conservative_rasterization_mode(vk::ConservativeRasterizationModeEXT::OVERESTIMATE)
            .extra_primitive_overestimation_size(extra);
        let mut raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0)
            .depth_bias_enable(bias_on)
            .depth_bias_constant_factor(bias_constant)
            .depth_bias_slope_factor(bias_slope);
        if desc.conservative {
            raster = raster.push_next(&mut conservative);
        }
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let (test, write, compare) = match desc.depth {
            None => (false, false, vk::CompareOp::ALWAYS),
            Some(Depth::Nearest(_)) => (true, true, vk::CompareOp::LESS),
            Some(Depth::Covered(_)) => (true, false, vk::CompareOp::GREATER),
        };
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(test)
            .depth_write_enable(write)
            .depth_compare_op(compare);
        let blend_attachments: Vec<vk::PipelineColorBlendAttachmentState> = desc
            .color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA)
                    .blend_enable(desc.additive_blend)
                    .src_color_blend_factor(vk::BlendFactor::ONE)
                    .dst_color_blend_factor(vk::BlendFactor::ONE)
                    .color_blend_op(vk::BlendOp::ADD)
                    .src_alpha_blend_factor(vk::BlendFactor::ONE)
                    .dst_alpha_blend_factor(vk::BlendFactor::ONE)
                    .alpha_blend_op(vk::BlendOp::ADD)
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(desc.color_formats)
            .depth_attachment_format(desc.depth.map_or(vk::Format::UNDEFINED, Depth::format));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stage_infos)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        // SAFETY: every state struct referenced by `info` is a local alive for the call.
        let pipelines = unsafe {
            gpu.shared
                .device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, e)| GpuError::Vulkan {
            what: format!("creating graphics pipeline {name}"),
            result: e,
        })?;
        core.raw = pipelines[0];
        gpu.shared.set_name(core.raw, name);
        Ok(RasterPipeline {
            core,
            depth: desc.depth,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stage_binding_more_descriptors_of_a_kind_than_the_device_allows_is_refused() {
        // Vulkan's minimums: 4 storage buffers and 16 sampled images per stage, 32 push
        // descriptors.
        let limits = DescriptorLimits {
            storage_buffers: 4,
            uniform_buffers: 12,
            sampled_images: 16,
            storage_images: 4,
            samplers: 16,
            push_descriptors: 32,
        };
        let interface = |kinds: &[DescriptorKind]| ShaderInterface {
            bindings: kinds
                .iter()
                .enumerate()
                .map(|(i, &k)| (i as u32, k))
                .collect(),
            ..ShaderInterface::default()
        };
        let four = [DescriptorKind::StorageBuffer; 4];
        assert!(check_descriptor_limits(&limits, "four", &interface(&four)).is_ok());
        let five = [DescriptorKind::StorageBuffer; 5];
        let message = match check_descriptor_limits(&limits, "five", &interface(&five)) {
            Err(e) => e.to_string(),
            Ok(()) => panic!("five storage buffers passed a limit of four"),
        };
        assert!(
            message.contains("five")
                && message.contains("binds 5 storage buffers; the device allows 4"),
            "{message}"
        );
        // Uniform texel buffers count as sampled images.
        let texels = [DescriptorKind::UniformTexelBuffer; 17];
        assert!(check_descriptor_limits(&limits, "texels", &interface(&texels)).is_err());
    }
}
