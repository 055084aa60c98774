//! LightWave's per-vertex gather, as the thesis shades (spec 002 §2.4): the indirect term of
//! every light at every vertex once per frame (front and back: vkgi's surfaces are two-sided),
//! interpolated across each triangle at every pixel. Each view gets an image of the triangle
//! each pixel sees, drawn with the G-buffer's geometry, so the interpolation knows its corners.

use ash::vk;

use super::bindings as ids;
use super::cpu::gather_normals;
use crate::gi::FrameContext;
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Image, ImageDesc,
    RasterPass, RasterPipeline, RasterPipelineDesc, Recorder, Specialization,
};
use crate::render::targets::View;
use crate::scene::Scene;
use crate::shader_shared::{LINEAR_WORKGROUP, RASTER_TRIANGLES, RASTER_VERTICES};
use crate::shaders;

crate::push_constants! {
    struct VertexGatherPush {
        vertex_count: u32,
        light_count: u32,
        per_light: u32,
    }
}

crate::push_constants! {
    struct TriangleIdsPush {
        view_projection: [[f32; 4]; 4],
    }
}

/// Workgroups along x every device allows (maxComputeWorkGroupCount's required minimum).
const MAX_WORKGROUPS_X: u32 = 65_535;

/// One view's triangle image and the depth it is drawn with.
struct TriangleIds {
    ids: Image,
    depth: Image,
}

pub struct VertexGather {
    vertex_count: u32,
    light_count: u32,
    normals: Buffer,
    /// Per vertex, per light: (front, back) gather.
    values: Buffer,
    gather: ComputePipeline,
    triangle_ids: RasterPipeline,
    /// Per view, made (again) when the view's size changes.
    views: Vec<TriangleIds>,
}

impl VertexGather {
    pub fn new(gpu: &Gpu, scene: &Scene, light_count: u32) -> anyhow::Result<VertexGather> {
        let vertex_count = scene.mesh.positions.len() as u32;
        let bytes = u64::from(vertex_count) * u64::from(light_count.max(1)) * 8;
        crate::render::targets::check_buffer(
            gpu,
            &format!("LightWave's gather at {vertex_count} vertices"),
            bytes,
        )?;
        let normals = gather_normals(&scene.mesh);
        Ok(VertexGather {
            vertex_count,
            light_count,
            normals: gpu.upload_storage_items("lightwave gather normals", normals.len(), |i| {
                normals[i].extend(0.0).to_array()
            })?,
            values: gpu.create_buffer(&BufferDesc::storage("lightwave vertex gather", bytes.max(16)))?,
            gather: ComputePipeline::new(
                gpu,
                "lightwave vertex gather",
                shaders::GI_LIGHTWAVE_VERTEX_GATHER_COMP,
                &Specialization::new(),
            )?,
            triangle_ids: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: "lightwave triangle ids",
                    vertex: shaders::GI_LIGHTWAVE_TRIANGLE_IDS_VERT,
                    fragment: Some(shaders::GI_LIGHTWAVE_TRIANGLE_IDS_FRAG),
                    color_formats: &[vk::Format::R32_UINT],
                    depth_format: Some(vk::Format::D32_SFLOAT),
                    depth_bias: None,
                },
            )?,
            views: Vec::new(),
        })
    }

    /// Gather at every vertex from `vpls` (`per_light` VPLs per light), and make sure every
    /// view has its triangle image.
    pub fn record(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        vpls: &Buffer,
        per_light: u32,
    ) -> GpuResult<()> {
        self.fit_views(rec.gpu(), ctx.views)?;
        rec.compute(&ComputePass {
            name: "lightwave vertex gather",
            pipeline: &self.gather,
            bindings: &[
                Binding::read(ids::VERTEX_GATHER_VERTICES, &ctx.scene.vertices),
                Binding::read(ids::VERTEX_GATHER_NORMALS, &self.normals),
                Binding::read(ids::VERTEX_GATHER_VPLS, vpls),
                Binding::write(ids::VERTEX_GATHER_OUT, &self.values),
            ],
            push: &VertexGatherPush {
                vertex_count: self.vertex_count,
                light_count: self.light_count,
                per_light,
            },
            threads: self.workgroups(),
        })
    }

    /// One workgroup per (vertex, light), in rows of at most `MAX_WORKGROUPS_X` (as threads).
    fn workgroups(&self) -> [u32; 3] {
        let total = (self.vertex_count * self.light_count).max(1);
        let columns = total.min(MAX_WORKGROUPS_X);
        [columns * LINEAR_WORKGROUP, total.div_ceil(columns), 1]
    }

    /// Draw the triangle each pixel of view `index` sees.
    pub fn record_view(&self, rec: &mut Recorder, ctx: &FrameContext, index: usize) -> GpuResult<()> {
        let view = &ctx.views[index];
        let targets = &self.views[index];
        rec.raster(&RasterPass {
            name: "lightwave triangle ids",
            pipeline: &self.triangle_ids,
            bindings: &[
                Binding::read(RASTER_VERTICES, &ctx.scene.vertices),
                Binding::read(RASTER_TRIANGLES, &ctx.scene.triangles),
            ],
            push: &TriangleIdsPush {
                view_projection: view.eye.view_projection.to_cols_array_2d(),
            },
            color: &[(&targets.ids, 0, [0.0; 4])],
            depth: Some((&targets.depth, 0)),
            vertex_count: ctx.scene.vertex_count,
        })
    }

    /// What the interpolation reads for view `index`, besides the shared gather bindings.
    pub fn bindings<'a>(&'a self, ctx: &'a FrameContext, index: usize) -> [Binding<'a>; 5] {
        [
            Binding::read(ids::GATHER_VERTICES, &ctx.scene.vertices),
            Binding::read(ids::GATHER_TRIANGLES, &ctx.scene.triangles),
            Binding::read(ids::GATHER_VERTEX_NORMALS, &self.normals),
            Binding::read(ids::GATHER_VERTEX_VALUES, &self.values),
            Binding::image_read(ids::GATHER_TRIANGLE_IDS, &self.views[index].ids),
        ]
    }

    /// The per-vertex values as the last frame left them: per vertex, per light, (front, back).
    pub fn read_values(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 2]>> {
        let bytes = gpu.read_buffer(&self.values)?;
        let count = (self.vertex_count * self.light_count) as usize;
        Ok(bytemuck::cast_slice::<u8, [f32; 2]>(&bytes)[..count].to_vec())
    }

    /// A triangle image per view, of the view's size.
    fn fit_views(&mut self, gpu: &Gpu, views: &[View]) -> GpuResult<()> {
        let fits = |t: &TriangleIds, v: &View| {
            (t.ids.extent.width, t.ids.extent.height) == (v.width(), v.height())
        };
        if self.views.len() == views.len() && self.views.iter().zip(views).all(|(t, v)| fits(t, v)) {
            return Ok(());
        }
        // Images of the old size may still be in flight.
        gpu.wait_idle()?;
        self.views = views
            .iter()
            .map(|v| {
                let image = |name, format, usage| {
                    gpu.create_image(&ImageDesc::new_2d(name, format, v.width(), v.height(), usage))
                };
                Ok(TriangleIds {
                    ids: image(
                        "lightwave triangle ids",
                        vk::Format::R32_UINT,
                        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
                    )?,
                    depth: image(
                        "lightwave triangle depth",
                        vk::Format::D32_SFLOAT,
                        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                    )?,
                })
            })
            .collect::<GpuResult<_>>()?;
        Ok(())
    }
}
