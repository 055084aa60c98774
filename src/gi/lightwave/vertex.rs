//! LightWave's per-vertex gather, as the thesis shades (spec 002 §2.4): the indirect term of
//! every light at every vertex once per frame (front and back: vkgi's surfaces are two-sided),
//! interpolated across each triangle at every pixel. Each view gets an image of the triangle
//! each pixel sees (gi/shared/triangle_ids.rs), so the interpolation knows its corners.

use super::bindings as ids;
use super::cpu::gather_normals;
use crate::gi::FrameContext;
use crate::gi::shared::triangle_ids::TriangleIds;
use crate::gpu::dispatch::rows_of_workgroups;
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
        slices: u32,
    }
}

/// Invocations the gather aims for: a mesh with fewer (vertex, light) pairs splits each pair's
/// VPLs into slices until about this many run (a GPU fills; a CPU device does not mind).
const TARGET_INVOCATIONS: u32 = 65_536;

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
                Binding::texels(ids::VERTEX_GATHER_VPLS, vpls),
                Binding::write(ids::VERTEX_GATHER_OUT, &self.values),
            ],
            push: &VertexGatherPush {
                vertex_count: self.vertex_count,
                light_count: self.light_count,
                per_light,
                slices: self.slices(),
            },
            threads: self.workgroups(),
        })
    }

    /// Slices of each (vertex, light) pair's VPLs: the power of two, at most a workgroup, that
    /// brings the invocations to [`TARGET_INVOCATIONS`].
    fn slices(&self) -> u32 {
        vpl_slices(self.vertex_count * self.light_count)
    }

    fn workgroups(&self) -> [u32; 3] {
        gather_threads(self.vertex_count * self.light_count, self.slices())
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

/// Slices for `pairs` (vertex, light) pairs: see [`VertexGather::slices`].
fn vpl_slices(pairs: u32) -> u32 {
    TARGET_INVOCATIONS
        .div_ceil(pairs.max(1))
        .next_power_of_two()
        .min(LINEAR_WORKGROUP)
}

/// The gather's threads for `pairs` (vertex, light) pairs in `slices`: a workgroup per
/// `LINEAR_WORKGROUP / slices` pairs, in rows of workgroups.
fn gather_threads(pairs: u32, slices: u32) -> [u32; 3] {
    rows_of_workgroups(pairs.div_ceil(LINEAR_WORKGROUP / slices), LINEAR_WORKGROUP)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::dispatch::MAX_WORKGROUPS_X;

    #[test]
    fn few_pairs_split_their_vpls_and_many_do_not() {
        // The Cornell box's vertices: a workgroup's worth of slices each.
        assert_eq!(vpl_slices(60), LINEAR_WORKGROUP);
        assert_eq!(vpl_slices(0), LINEAR_WORKGROUP);
        // four-boxes' 272 vertices and 16 lights: 4352 pairs, 16 slices make 69 632.
        assert_eq!(vpl_slices(272 * 16), 16);
        assert_eq!(vpl_slices(TARGET_INVOCATIONS / 2), 2);
        // atrium:1's 37 381 vertices and 2 lights: one slice.
        assert_eq!(vpl_slices(37_381 * 2), 1);
        assert_eq!(vpl_slices(u32::MAX), 1);
    }

    #[test]
    fn the_gather_covers_every_pair_in_rows_of_workgroups() {
        for (pairs, slices) in [(6, 64), (2400, 32), (72_600, 1), (5_000_000, 1), (3_000_000, 2)] {
            let [x, y, z] = gather_threads(pairs, slices);
            let (columns, rows) = (x / LINEAR_WORKGROUP, y);
            assert_eq!((x % LINEAR_WORKGROUP, z), (0, 1));
            assert!(columns <= MAX_WORKGROUPS_X);
            // The shader's pair of the last lane of the last workgroup reaches the last pair.
            let pairs_per_group = LINEAR_WORKGROUP / slices;
            let covered = u64::from(columns) * u64::from(rows) * u64::from(pairs_per_group);
            assert!(covered >= u64::from(pairs), "{pairs} pairs in {slices} slices");
            assert!(covered < u64::from(pairs) + u64::from(columns * pairs_per_group));
        }
        // Past one row: 5 000 000 pairs a slice, 78 125 workgroups, two rows.
        assert_eq!(gather_threads(5_000_000, 1)[1], 2);
    }
}
