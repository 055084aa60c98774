//! LightWave's per-vertex gather, as the thesis shades (spec 002 §2.4): the indirect term of
//! every light at every vertex once per frame (front and back: vkgi's surfaces are two-sided),
//! interpolated across each triangle at every pixel. Each view gets an image of the triangle
//! each pixel sees (gi/shared/triangle_ids.rs), so the interpolation knows its corners.

use super::bindings as ids;
use super::cpu::gather_normals;
use crate::gi::FrameContext;
use crate::gi::shared::triangle_ids::TriangleIds;
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Recorder,
    Specialization,
};
use crate::scene::Scene;
use crate::shader_shared::LINEAR_WORKGROUP;
use crate::shaders;

crate::push_constants! {
    struct VertexGatherPush {
        vertex_count: u32,
        light_count: u32,
        per_light: u32,
    }
}

/// Workgroups along x every device allows (maxComputeWorkGroupCount's required minimum).
const MAX_WORKGROUPS_X: u32 = 65_535;

pub struct VertexGather {
    vertex_count: u32,
    light_count: u32,
    normals: Buffer,
    /// Per vertex, per light: (front, back) gather.
    values: Buffer,
    gather: ComputePipeline,
    triangle_ids: TriangleIds,
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
            triangle_ids: TriangleIds::new(gpu, "lightwave triangle ids")?,
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
        self.triangle_ids.fit_views(rec.gpu(), ctx.views)?;
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
        self.triangle_ids.record_view(rec, ctx, index)
    }

    /// What the interpolation reads for view `index`, besides the shared gather bindings.
    pub fn bindings<'a>(&'a self, ctx: &'a FrameContext, index: usize) -> [Binding<'a>; 5] {
        [
            Binding::read(ids::GATHER_VERTICES, &ctx.scene.vertices),
            Binding::read(ids::GATHER_TRIANGLES, &ctx.scene.triangles),
            Binding::read(ids::GATHER_VERTEX_NORMALS, &self.normals),
            Binding::read(ids::GATHER_VERTEX_VALUES, &self.values),
            Binding::image_read(ids::GATHER_TRIANGLE_IDS, self.triangle_ids.image(index)),
        ]
    }

    /// The per-vertex values as the last frame left them: per vertex, per light, (front, back).
    pub fn read_values(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 2]>> {
        let bytes = gpu.read_buffer(&self.values)?;
        let count = (self.vertex_count * self.light_count) as usize;
        Ok(bytemuck::cast_slice::<u8, [f32; 2]>(&bytes)[..count].to_vec())
    }
}
