//! The lookup: indirect light from one lattice, or from both lattices of ILPV's two scales in
//! one pass, so that the G-buffer is read and the HDR image read and written once. Where the
//! frame's direct lighting is a fragment pass, the lookup is drawn inside it
//! (`lpv/lit_lookup.{vert,frag}`): the G-buffer read once for both and the HDR image written
//! once; else, or when the frame asks (`FrameOptions::lookup_apart`), as a pass of its own
//! after it (`lpv/lookup.{vert,frag}`).

use ash::vk;
use glam::Vec3;

use super::bindings as ids;
use super::cost;
use crate::gi::{FrameContext, PixelPass};
use crate::gpu::{
    Binding, Buffer, Draw, Gpu, GpuResult, Image, RasterPass, RasterPipeline, Recorder,
    Sampler, Specialization,
};
use crate::render::full_screen::{Blend, FullScreenShaders, full_screen_with};
use crate::render::passes::{DirectDraw, DirectShape};
use crate::render::targets::HDR_FORMAT;
use crate::scene::Scene;
use crate::shaders;

/// The pass's name in the profile.
const LOOKUP: &str = "lpv lookup";
/// The name of direct lighting with the lookup in the profile.
const LIT_LOOKUP: &str = "direct lighting + lpv lookup";

/// The lookup of `lattices` lattices as per-pixel passes of the profile: apart, and inside
/// direct lighting (where its bound adds to direct lighting's what the lookup adds to it: no
/// bytes, since the G-buffer is read and the HDR pixel written for direct lighting anyway, and
/// the lookup's arithmetic but the normal's normalisation).
pub fn lookup_passes(lattices: u32) -> [PixelPass; 2] {
    let flops = cost::lookup_flops_per_pixel(lattices);
    [
        PixelPass {
            pass: LOOKUP,
            bytes_per_pixel: cost::LOOKUP_BYTES_PER_PIXEL,
            flops_per_pixel: flops,
            with_direct_lighting: false,
        },
        PixelPass {
            pass: LIT_LOOKUP,
            bytes_per_pixel: 0.0,
            flops_per_pixel: flops - cost::NORMALISE_FLOPS,
            with_direct_lighting: true,
        },
    ]
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

/// The fields' constants: `LOOKUP_FIELD_WORDS` words of four.
type FieldWords = [[f32; 4]; ids::LOOKUP_FIELD_WORDS as usize];

/// The fields' constants as `lpv/lookup_fields.glsl` reads them: per field the origin of its
/// images and the cell size, the images' size, and (scale, offset). A one-field lookup repeats
/// its field, which the shader leaves be.
fn field_words(fields: &[LookupField]) -> FieldWords {
    let (near, far) = (&fields[0], &fields[fields.len() - 1]);
    let dims = |f: &LookupField| f.image_dims().map(|d| f32::from_bits(d as u32));
    [
        near.origin_cell(),
        far.origin_cell(),
        dims(near),
        dims(far),
        [near.scale, near.offset, 0.0, 0.0],
        [far.scale, far.offset, 0.0, 0.0],
    ]
}

/// The lookup's pipelines for a number of fields (1 or 2), its trilinear sampler and the buffer
/// of the fields' constants.
pub struct Lookup {
    /// The lookup as a pass of its own.
    apart: RasterPipeline,
    /// Direct lighting with the lookup, for direct lighting of this shape (None: direct
    /// lighting is a compute pass for the scene the lookup was built for).
    lit: Option<(DirectShape, RasterPipeline)>,
    /// Trilinear, clamped to the edge: the images' border of zero cells makes the outside
    /// of the lattice transparent black (as if it were empty).
    sampler: Sampler,
    /// The fields' constants (`field_words`), written once: a lattice's place, size and scale
    /// stay as built.
    words: Buffer,
    /// The same words on the CPU, to check that a draw is given the fields it was built for.
    written: FieldWords,
    fields: usize,
}

impl Lookup {
    /// The lookup of `fields` (one or two) in `scene`.
    pub fn new(gpu: &Gpu, scene: &Scene, fields: &[LookupField]) -> GpuResult<Lookup> {
        assert!(matches!(fields.len(), 1 | 2), "the lookup reads one or two fields");
        let written = field_words(fields);
        let count = fields.len();
        let own = |spec: Specialization| spec.with_u32(ids::LOOKUP_FIELDS_CONSTANT, count as u32);
        let lit = match DirectShape::of(scene, &scene.raster_lights()) {
            Some(shape) => {
                let pipeline = full_screen_with(
                    gpu,
                    LIT_LOOKUP,
                    FullScreenShaders {
                        vertex: shaders::GI_LPV_LIT_LOOKUP_VERT,
                        fragment: shaders::GI_LPV_LIT_LOOKUP_FRAG,
                    },
                    HDR_FORMAT,
                    Blend::Replace,
                    &own(shape.specialization().clone()),
                )?;
                Some((shape, pipeline))
            }
            None => None,
        };
        Ok(Lookup {
            apart: full_screen_with(
                gpu,
                LOOKUP,
                FullScreenShaders {
                    vertex: shaders::GI_LPV_LOOKUP_VERT,
                    fragment: shaders::GI_LPV_LOOKUP_FRAG,
                },
                HDR_FORMAT,
                Blend::Add,
                &own(Specialization::new()),
            )?,
            lit,
            sampler: gpu
                .create_sampler(vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?,
            words: gpu.upload_storage("lookup fields", bytemuck::bytes_of(&written))?,
            written,
            fields: count,
        })
    }

    /// The bindings of `fields`' lattices and of their constants.
    fn field_bindings<'a>(&'a self, fields: &[LookupField<'a>]) -> Vec<Binding<'a>> {
        assert_eq!(fields.len(), self.fields, "the lookup was built for {} fields", self.fields);
        debug_assert_eq!(
            field_words(fields),
            self.written,
            "the lookup was built for other fields"
        );
        // A one-field lookup binds its lattice in the far slots too; the shader leaves them be.
        let [r, g, b] = fields[0].images;
        let [far_r, far_g, far_b] = fields[fields.len() - 1].images;
        vec![
            Binding::sampled(ids::LOOKUP_LATTICE_R, r, &self.sampler),
            Binding::sampled(ids::LOOKUP_LATTICE_G, g, &self.sampler),
            Binding::sampled(ids::LOOKUP_LATTICE_B, b, &self.sampler),
            Binding::sampled(ids::LOOKUP_FAR_LATTICE_R, far_r, &self.sampler),
            Binding::sampled(ids::LOOKUP_FAR_LATTICE_G, far_g, &self.sampler),
            Binding::sampled(ids::LOOKUP_FAR_LATTICE_B, far_b, &self.sampler),
            Binding::read(ids::LOOKUP_FIELDS, &self.words),
        ]
    }

    /// Add `fields`' indirect light to view `view`'s HDR image, after its direct lighting.
    pub fn record(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        fields: &[LookupField],
    ) -> GpuResult<()> {
        let view = &ctx.views[view];
        let gb = &view.gbuffer;
        let mut bindings = self.field_bindings(fields);
        bindings.extend([
            Binding::image_read(ids::LOOKUP_GBUFFER_POSITION, &gb.position),
            Binding::image_read(ids::LOOKUP_GBUFFER_NORMAL, &gb.normal),
            Binding::image_read(ids::LOOKUP_GBUFFER_ALBEDO, &gb.albedo),
        ]);
        rec.raster(&RasterPass {
            name: LOOKUP,
            pipeline: &self.apart,
            bindings: &bindings,
            push: &(),
            color: &[(&view.hdr, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(3),
            keep_contents: true,
        })
    }

    /// Draw `direct` with `fields`' indirect light added, if this lookup was built for
    /// direct lighting of its shape (false: nothing recorded).
    pub fn record_lit(
        &self,
        rec: &mut Recorder,
        direct: &DirectDraw,
        fields: &[LookupField],
    ) -> GpuResult<bool> {
        let Some((_, pipeline)) = self.lit.as_ref().filter(|(shape, _)| shape == direct.shape)
        else {
            return Ok(false);
        };
        let mut bindings = direct.bindings.clone();
        bindings.extend(self.field_bindings(fields));
        rec.raster(&RasterPass {
            name: LIT_LOOKUP,
            pipeline,
            bindings: &bindings,
            push: direct.push(),
            color: &[(direct.hdr, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(3),
            keep_contents: false,
        })?;
        Ok(true)
    }
}
