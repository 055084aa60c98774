//! The lookup pass: indirect light from one lattice, or from both lattices of ILPV's two
//! scales in one pass, so that the G-buffer is read and the HDR image read and written once.

use ash::vk;
use glam::Vec3;

use super::bindings as ids;
use super::cost;
use crate::gi::{FrameContext, PixelPass};
use crate::gpu::{
    Binding, Draw, Gpu, GpuResult, Image, RasterPass, RasterPipeline, Recorder, Sampler,
    Specialization,
};
use crate::render::full_screen::{Blend, FullScreenShaders, full_screen_with};
use crate::render::targets::HDR_FORMAT;
use crate::shaders;

/// The pass's name in the profile.
const LOOKUP: &str = "lpv lookup";

crate::push_constants! {
    struct LookupPush {
        origin_cell: [[f32; 4]; 2],
        dims: [[i32; 4]; 2],
        scale_offset: [[f32; 4]; 2],
    }
}

/// The lookup of `lattices` lattices as a per-pixel pass of the profile.
pub fn lookup_pass(lattices: u32) -> PixelPass {
    PixelPass {
        pass: LOOKUP,
        bytes_per_pixel: cost::LOOKUP_BYTES_PER_PIXEL,
        flops_per_pixel: cost::lookup_flops_per_pixel(lattices),
    }
}

/// Cells of zero around the lattice in the lookup's 3-D images: the lookup samples them
/// clamped to the edge, which costs lavapipe's sampler less than a border colour
/// (docs/performance.md) and gives the same transparent black outside the lattice.
pub const LOOKUP_BORDER: u32 = 1;

/// One lattice as the lookup reads it.
pub struct LookupField<'a> {
    /// The R, G and B lattices as 3-D images, each inside a border of [`LOOKUP_BORDER`] zero
    /// cells.
    pub images: &'a [Image; 3],
    /// The corner of the lattice's cell (0, 0, 0).
    pub origin: Vec3,
    pub cell_size: f32,
    pub dims: [i32; 4],
    /// Intensity per cell to radiance: the method's scale over π cell².
    pub scale: f32,
    /// How far along the normal the lookup moves, in cells.
    pub offset: f32,
}

impl LookupField<'_> {
    /// The corner of the images' texel (0, 0, 0), and the cell size.
    fn origin_cell(&self) -> [f32; 4] {
        let origin = self.origin - Vec3::splat(self.cell_size * LOOKUP_BORDER as f32);
        [origin.x, origin.y, origin.z, self.cell_size]
    }

    /// The images' size in texels.
    fn image_dims(&self) -> [i32; 4] {
        let [x, y, z, _] = self.dims.map(|d| d + 2 * LOOKUP_BORDER as i32);
        [x, y, z, 0]
    }
}

/// The lookup pipeline for a number of fields (1 or 2), and its trilinear sampler.
pub struct Lookup {
    pipeline: RasterPipeline,
    /// Trilinear, clamped to the edge: the images' border of zero cells makes the outside
    /// of the lattice transparent black (as if it were empty).
    sampler: Sampler,
    fields: usize,
}

impl Lookup {
    pub fn new(gpu: &Gpu, fields: usize) -> GpuResult<Lookup> {
        assert!(matches!(fields, 1 | 2), "the lookup reads one or two fields");
        let spec = Specialization::new().with_u32(0, fields as u32);
        Ok(Lookup {
            pipeline: full_screen_with(
                gpu,
                LOOKUP,
                FullScreenShaders {
                    vertex: shaders::GI_LPV_LOOKUP_VERT,
                    fragment: shaders::GI_LPV_LOOKUP_FRAG,
                },
                HDR_FORMAT,
                Blend::Add,
                &spec,
            )?,
            sampler: gpu
                .create_sampler(vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?,
            fields,
        })
    }

    /// Add `fields`' indirect light to view `view`'s HDR image.
    pub fn record(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        fields: &[LookupField],
    ) -> GpuResult<()> {
        assert_eq!(fields.len(), self.fields, "the lookup was built for {} fields", self.fields);
        // A one-field lookup binds its lattice in the far slots too; the shader leaves them be.
        let far = &fields[fields.len() - 1];
        let near = &fields[0];
        let view = &ctx.views[view];
        let push = LookupPush {
            origin_cell: [near.origin_cell(), far.origin_cell()],
            dims: [near.image_dims(), far.image_dims()],
            scale_offset: [
                [near.scale, near.offset, 0.0, 0.0],
                [far.scale, far.offset, 0.0, 0.0],
            ],
        };
        let gb = &view.gbuffer;
        let [r, g, b] = near.images;
        let [far_r, far_g, far_b] = far.images;
        rec.raster(&RasterPass {
            name: LOOKUP,
            pipeline: &self.pipeline,
            bindings: &[
                Binding::image_read(ids::LOOKUP_GBUFFER_POSITION, &gb.position),
                Binding::image_read(ids::LOOKUP_GBUFFER_NORMAL, &gb.normal),
                Binding::image_read(ids::LOOKUP_GBUFFER_ALBEDO, &gb.albedo),
                Binding::sampled(ids::LOOKUP_LATTICE_R, r, &self.sampler),
                Binding::sampled(ids::LOOKUP_LATTICE_G, g, &self.sampler),
                Binding::sampled(ids::LOOKUP_LATTICE_B, b, &self.sampler),
                Binding::sampled(ids::LOOKUP_FAR_LATTICE_R, far_r, &self.sampler),
                Binding::sampled(ids::LOOKUP_FAR_LATTICE_G, far_g, &self.sampler),
                Binding::sampled(ids::LOOKUP_FAR_LATTICE_B, far_b, &self.sampler),
            ],
            push: &push,
            color: &[(&view.hdr, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(3),
            keep_contents: true,
        })
    }
}
