//! The lookup: indirect light from one lattice, or from both lattices of ILPV's two scales in
//! one pass, so that the G-buffer is read and the HDR image read and written once. Where the
//! frame's direct lighting is a fragment pass, the lookup is drawn inside it
//! (`lpv/lit_lookup.{vert,frag}`): the G-buffer read once for both and the HDR image written
//! once; else, or when the frame asks (`FrameOptions::lookup_apart`), as a pass of its own
//! after it: a fragment pass (`lpv/lookup.{vert,frag}`) or, where the device runs the compute
//! form of the per-pixel passes (`DeviceInfo::pixel_passes`: GPUs), a compute pass
//! (`lpv/lookup.comp`).
//!
//! At `--lookup-resolution half` the lattices are looked up at every second pixel in x and y
//! (`lpv/lookup_half.frag`, into a quarter-size image per view) and spread over the pixels by a
//! depth- and normal-aware upsample (`lpv/upsample.glsl`, mirrored in f64 by
//! [`super::upsample`]), drawn inside direct lighting or apart as above; `vkgi report` scores
//! its error against full resolution.
//!
//! The lattices are read one of three ways ([`LookupFilter`], `--lookup-filter`): copied into 3-D
//! images inside a border of zero cells that the sampler filters trilinearly (one fetch per
//! channel, the texture unit's work on a GPU), or the lattice buffers read as texels and
//! interpolated in the shader (eight fetches per channel, which lavapipe runs in about half the
//! time of its software filter; docs/performance.md), each pixel fetching its own or the lanes
//! of a subgroup fetching the cells around their points together. The texel forms give the same
//! bits, and the sampler the same light within float rounding.

use ash::vk;
use glam::Vec3;

use super::bindings as ids;
use super::cost;
use super::lattice::CellOrder;
use super::upsample::half_size;
use crate::gi::{FrameContext, PixelPass};
use crate::gpu::{
    Binding, Buffer, ComputePass, ComputePipeline, Draw, Gpu, GpuError, GpuResult, Image,
    ImageDesc, PixelPasses, PushConstants, RasterPass, RasterPipeline, Recorder, Sampler,
    Specialization,
};
use crate::render::full_screen::{Blend, FullScreenShaders, Pixels, full_screen, full_screen_with};
use crate::render::passes::{DirectDraw, LitPipeline};
use crate::render::targets::{HDR_FORMAT, View};
use crate::scene::Scene;
use crate::shaders;

/// The pass's name in the profile.
const LOOKUP: &str = "lpv lookup";
/// The name of direct lighting with the lookup in the profile.
const LIT_LOOKUP: &str = "direct lighting + lpv lookup";
/// `--lookup-resolution half`: the lookup into the quarter-size image, the upsample apart and
/// the upsample inside direct lighting.
const HALF_LOOKUP: &str = "lpv half-resolution lookup";
const UPSAMPLE: &str = "lpv upsample";
const LIT_UPSAMPLE: &str = "direct lighting + lpv upsample";

/// The quarter-size image of `--lookup-resolution half` (lpv/half_light.glsl's texels).
const HALF_LIGHT_FORMAT: vk::Format = vk::Format::R32G32B32A32_UINT;

/// Where the lookup evaluates the lattices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum LookupResolution {
    /// At every pixel.
    Full,
    /// At every second pixel in x and y, spread over the pixels by a depth- and normal-aware
    /// upsample.
    Half,
}

/// The lookup of `lattices` lattices at `resolution` as per-pixel passes of the profile. Full:
/// apart, and inside direct lighting (where its bound adds to direct lighting's what the lookup
/// adds to it: no bytes, since the G-buffer is read and the HDR pixel written for direct
/// lighting anyway, and the lookup's arithmetic but the normal's normalisation). Half: the
/// lookup at a quarter of the pixels, then the upsample apart or inside direct lighting.
pub fn lookup_passes(lattices: u32, resolution: LookupResolution) -> Vec<PixelPass> {
    // What the pass adds to direct lighting's bytes inside it: nothing for the lookup (its
    // lattices stay in cache), the quarter of a texel each pixel's upsample reads.
    let (apart, lit, bytes, lit_bytes, flops) = match resolution {
        LookupResolution::Full => (
            LOOKUP,
            LIT_LOOKUP,
            cost::LOOKUP_BYTES_PER_PIXEL,
            0.0,
            cost::lookup_flops_per_pixel(lattices),
        ),
        LookupResolution::Half => (
            UPSAMPLE,
            LIT_UPSAMPLE,
            cost::UPSAMPLE_BYTES_PER_PIXEL,
            cost::UPSAMPLE_TEXEL_BYTES_PER_PIXEL,
            cost::UPSAMPLE_FLOPS_PER_PIXEL,
        ),
    };
    let mut passes = vec![
        PixelPass {
            pass: apart,
            bytes_per_pixel: bytes,
            flops_per_pixel: flops,
            with_direct_lighting: false,
            background_bytes: Some(cost::BACKGROUND_TEST_BYTES),
        },
        PixelPass {
            pass: lit,
            bytes_per_pixel: lit_bytes,
            flops_per_pixel: flops - cost::NORMALISE_FLOPS,
            with_direct_lighting: true,
            background_bytes: Some(0.0),
        },
    ];
    if resolution == LookupResolution::Half {
        passes.push(PixelPass {
            pass: HALF_LOOKUP,
            bytes_per_pixel: cost::HALF_LOOKUP_BYTES_PER_TEXEL / 4.0,
            flops_per_pixel: cost::half_lookup_flops_per_texel(lattices) / 4.0,
            with_direct_lighting: false,
            background_bytes: None,
        });
    }
    passes
}

crate::push_constants! {
    /// The eye of the view, for `--lookup-resolution half`'s passes (lpv/lookup_half.frag,
    /// lpv/upsample.frag).
    struct EyePush {
        eye: [f32; 4],
    }
}

impl EyePush {
    fn of(view: &View) -> EyePush {
        EyePush {
            eye: view.eye.position.extend(1.0).to_array(),
        }
    }
}

/// How the lookup reads and interpolates the lattices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum LookupFilter {
    /// Copies of the lattices as 3-D images that the sampler filters trilinearly.
    Sampler,
    /// The lattice buffers read as texels, the eight cells around a point weighted in the
    /// shader, each pixel fetching its own.
    Texels,
    /// As [`LookupFilter::Texels`], the fetches shared across a subgroup: each lane fetches one
    /// of the eight cells around the first waiting lane's point and every lane whose point lies
    /// among them takes all eight by shuffles, a round for each set of cells the subgroup's
    /// points need (three fetches a lane a round, against 24 a pixel). The same sums in the
    /// same order as the per-pixel form: the same bits.
    SharedTexels,
}

impl LookupFilter {
    /// `--lookup-filter auto`: on a CPU device, whose sampler filters in software, texels shared
    /// across the subgroup where it can ([`LookupFilter::can_share_texels`]; else texels); the
    /// sampler on a GPU.
    pub fn for_device(gpu: &Gpu) -> LookupFilter {
        match (gpu.info.is_cpu(), LookupFilter::can_share_texels(gpu)) {
            (true, true) => LookupFilter::SharedTexels,
            (true, false) => LookupFilter::Texels,
            (false, _) => LookupFilter::Sampler,
        }
    }

    /// `gpu` can run [`LookupFilter::SharedTexels`]: its fragment and compute shaders ballot,
    /// vote and shuffle across subgroups of at least the eight lanes that fetch a point's eight
    /// cells.
    pub fn can_share_texels(gpu: &Gpu) -> bool {
        gpu.info.pixel_subgroup_shuffles && gpu.info.subgroup_size >= 8
    }

    /// The lookup reads the lattice buffers as texels (not 3-D images).
    pub fn reads_texels(self) -> bool {
        self != LookupFilter::Sampler
    }

    /// The lookup's shaders that read the lattices this way.
    fn shaders(self) -> FilterShaders {
        match self {
            LookupFilter::Sampler => FilterShaders {
                lit: shaders::GI_LPV_LIT_LOOKUP_FRAG,
                apart: shaders::GI_LPV_LOOKUP_FRAG,
                apart_compute: shaders::GI_LPV_LOOKUP_COMP,
                half: shaders::GI_LPV_LOOKUP_HALF_FRAG,
            },
            LookupFilter::Texels => FilterShaders {
                lit: shaders::GI_LPV_LIT_LOOKUP_TEXELS_FRAG,
                apart: shaders::GI_LPV_LOOKUP_TEXELS_FRAG,
                apart_compute: shaders::GI_LPV_LOOKUP_TEXELS_COMP,
                half: shaders::GI_LPV_LOOKUP_HALF_TEXELS_FRAG,
            },
            LookupFilter::SharedTexels => FilterShaders {
                lit: shaders::GI_LPV_LIT_LOOKUP_SHARED_TEXELS_FRAG,
                apart: shaders::GI_LPV_LOOKUP_SHARED_TEXELS_FRAG,
                apart_compute: shaders::GI_LPV_LOOKUP_SHARED_TEXELS_COMP,
                half: shaders::GI_LPV_LOOKUP_HALF_SHARED_TEXELS_FRAG,
            },
        }
    }
}

/// The fragment (or compute) shaders of the lookup's passes for one [`LookupFilter`].
struct FilterShaders {
    /// Direct lighting with the lookup (`lpv/lit_lookup*.frag`).
    lit: &'static [u8],
    /// The lookup apart, a fragment pass (`lpv/lookup*.frag`).
    apart: &'static [u8],
    /// The lookup apart, a compute pass (`lpv/lookup*.comp`).
    apart_compute: &'static [u8],
    /// The lookup at half resolution (`lpv/lookup_half*.frag`).
    half: &'static [u8],
}

/// What the lookup reads of one lattice, by its [`LookupFilter`].
pub enum LatticeReads<'a> {
    /// The R, G and B lattices as 3-D images, each inside a border of [`LOOKUP_BORDER`] zero
    /// cells.
    Images(&'a [Image; 3]),
    /// The R, G and B lattice buffers, with texel views.
    Texels([&'a Buffer; 3]),
}

impl LatticeReads<'_> {
    /// These are the lattice buffers, read as texels.
    fn are_texels(&self) -> bool {
        matches!(self, LatticeReads::Texels(_))
    }

    /// Cells of zero around the lattice in what is read.
    fn border(&self) -> u32 {
        match self {
            LatticeReads::Images(_) => LOOKUP_BORDER,
            LatticeReads::Texels(_) => 0,
        }
    }
}

/// Cells of zero around the lattice in the lookup's 3-D images: the lookup samples them
/// clamped to the edge, which costs lavapipe's sampler less than a border colour
/// (docs/performance-log.md, "This round (27 November): the lookup's border") and gives the
/// same transparent black outside the lattice.
pub const LOOKUP_BORDER: u32 = 1;

/// One lattice as the lookup reads it.
pub struct LookupField<'a> {
    /// The R, G and B lattices, as its lookup's filter reads them.
    pub lattices: LatticeReads<'a>,
    /// The corner of the lattice's cell (0, 0, 0).
    pub origin: Vec3,
    pub cell_size: f32,
    pub dims: [i32; 4],
    /// How the lattice buffers hold the cells (the texels' order; images are copied from
    /// buffers of rows).
    pub cell_order: CellOrder,
    /// Intensity per cell to radiance: the method's scale over π cell².
    pub scale: f32,
    /// How far along the normal the lookup moves, in cells.
    pub offset: f32,
}

impl LookupField<'_> {
    /// The corner of the cell (0, 0, 0) of what is read (the border included), and the cell
    /// size.
    fn origin_cell(&self) -> [f32; 4] {
        let border = self.lattices.border() as f32;
        let origin = self.origin - Vec3::splat(self.cell_size * border);
        [origin.x, origin.y, origin.z, self.cell_size]
    }

    /// The cells of what is read (the border included), and 1 where the texels hold them in
    /// columns (`lpv/lattice.glsl`'s `cell_strides`).
    fn read_dims(&self) -> [i32; 4] {
        let border = self.lattices.border() as i32;
        let [x, y, z, _] = self.dims.map(|d| d + 2 * border);
        [x, y, z, self.cell_order.columns_flag() as i32]
    }
}

/// The fields' constants: `LOOKUP_FIELD_WORDS` words of four.
type FieldWords = [[f32; 4]; ids::LOOKUP_FIELD_WORDS as usize];

/// The fields' constants as `lpv/lookup_fields.glsl` reads them: per field the origin of what
/// it reads and the cell size, the cells it reads, and (scale, offset). A one-field lookup repeats
/// its field, which the shader leaves be.
fn field_words(fields: &[LookupField]) -> FieldWords {
    let (near, far) = (&fields[0], &fields[fields.len() - 1]);
    let dims = |f: &LookupField| f.read_dims().map(|d| f32::from_bits(d as u32));
    [
        near.origin_cell(),
        far.origin_cell(),
        dims(near),
        dims(far),
        [near.scale, near.offset, 0.0, 0.0],
        [far.scale, far.offset, 0.0, 0.0],
    ]
}

/// `--lookup-resolution half`'s lookup into a quarter-size image per view.
struct HalfLookup {
    pipeline: RasterPipeline,
    /// Per view (by index), its image of the lattices' light (lpv/half_light.glsl), once
    /// fitted.
    images: Vec<Option<Image>>,
}

/// The lookup (or at half resolution the upsample) as a pass of its own, in the form the device
/// runs at full resolution (the upsample is a fragment pass everywhere).
enum Apart {
    /// A full-screen triangle whose output the blend adds to the HDR image.
    Fragment(RasterPipeline),
    /// A compute pass that adds to the HDR image as a storage image.
    Compute(ComputePipeline),
}

/// The lookup's pipelines for a number of fields (1 or 2) read one way, its trilinear sampler
/// where it reads images, and the buffer of the fields' constants.
pub struct Lookup {
    /// The lookup as a pass of its own (at half resolution, the upsample's).
    apart: Apart,
    /// Direct lighting with the lookup (at half resolution, with the upsample), for direct
    /// lighting of this shape (None: direct lighting is a compute pass for the scene the lookup
    /// was built for).
    lit: Option<LitPipeline>,
    /// At half resolution, the lookup the upsample reads.
    half: Option<HalfLookup>,
    /// How the fields are read.
    filter: LookupFilter,
    /// With [`LookupFilter::Sampler`]: trilinear, clamped to the edge (the images' border of
    /// zero cells makes the outside of the lattice transparent black, as if it were empty).
    sampler: Option<Sampler>,
    /// The fields' constants (`field_words`), written once: a lattice's place, size and scale
    /// stay as built.
    words: Buffer,
    /// The same words on the CPU, to check that a draw is given the fields it was built for.
    written: FieldWords,
    fields: usize,
}

impl Lookup {
    /// The lookup of `fields` (one or two, read the same way: `filter`'s) in `scene`, at
    /// `resolution`.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        fields: &[LookupField],
        resolution: LookupResolution,
        filter: LookupFilter,
    ) -> GpuResult<Lookup> {
        if !matches!(fields.len(), 1 | 2) {
            return Err(GpuError::Setup(format!(
                "the lookup reads one or two fields, not {}",
                fields.len()
            )));
        }
        let texels = filter.reads_texels();
        if fields.iter().any(|f| f.lattices.are_texels() != texels) {
            return Err(GpuError::Setup(
                "the fields of one lookup must be read the lookup's way".into(),
            ));
        }
        let filter_shaders = filter.shaders();
        let columns = |f: &LookupField| f.cell_order == CellOrder::Columns;
        if !texels && fields.iter().any(columns) {
            return Err(GpuError::Setup(
                "the sampler's images are copied from lattices of rows, not of columns".into(),
            ));
        }
        let written = field_words(fields);
        let count = fields.len();
        let own = |spec: Specialization| spec.with_u32(ids::LOOKUP_FIELDS_CONSTANT, count as u32);
        let (apart, lit, half) = match resolution {
            LookupResolution::Full => {
                let shaders = FullScreenShaders {
                    vertex: shaders::GI_LPV_LIT_LOOKUP_VERT,
                    fragment: filter_shaders.lit,
                };
                let lit = LitPipeline::new(gpu, scene, LIT_LOOKUP, shaders, own)?;
                let shaders = FullScreenShaders {
                    vertex: shaders::GI_LPV_LOOKUP_VERT,
                    fragment: filter_shaders.apart,
                };
                let spec = own(Specialization::new());
                let apart = match gpu.info.pixel_passes {
                    PixelPasses::Fragment => Apart::Fragment(full_screen_with(
                        gpu,
                        LOOKUP,
                        shaders,
                        (HDR_FORMAT, Pixels::Covered),
                        Blend::Add,
                        &spec,
                    )?),
                    PixelPasses::Compute => Apart::Compute(ComputePipeline::new(
                        gpu,
                        LOOKUP,
                        filter_shaders.apart_compute,
                        &spec,
                    )?),
                };
                (apart, lit, None)
            }
            LookupResolution::Half => {
                let shaders = FullScreenShaders {
                    vertex: shaders::RASTER_LIGHTING_VERT,
                    fragment: shaders::GI_LPV_LIT_UPSAMPLE_FRAG,
                };
                let lit = LitPipeline::new(gpu, scene, LIT_UPSAMPLE, shaders, |spec| spec)?;
                let apart = Apart::Fragment(full_screen(
                    gpu,
                    UPSAMPLE,
                    shaders::GI_LPV_UPSAMPLE_FRAG,
                    (HDR_FORMAT, Pixels::Covered),
                    Blend::Add,
                    &Specialization::new(),
                )?);
                let shaders = FullScreenShaders {
                    vertex: shaders::GI_LPV_LOOKUP_VERT,
                    fragment: filter_shaders.half,
                };
                let spec = own(Specialization::new());
                let pipeline = full_screen_with(
                    gpu,
                    HALF_LOOKUP,
                    shaders,
                    (HALF_LIGHT_FORMAT, Pixels::All),
                    Blend::Replace,
                    &spec,
                )?;
                let half = HalfLookup {
                    pipeline,
                    images: Vec::new(),
                };
                (apart, lit, Some(half))
            }
        };
        Ok(Lookup {
            apart,
            lit,
            half,
            filter,
            sampler: match filter {
                LookupFilter::Sampler => Some(
                    gpu.create_sampler(vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?,
                ),
                LookupFilter::Texels | LookupFilter::SharedTexels => None,
            },
            words: gpu.upload_storage("lookup fields", bytemuck::bytes_of(&written))?,
            written,
            fields: count,
        })
    }

    /// A line for the profile: where the lookup evaluates the lattices, and how it reads them.
    pub fn describe(&self) -> String {
        let resolution = match self.half {
            None => "at every pixel",
            Some(_) => "at half resolution (every second pixel in x and y), spread over the pixels by a depth- and normal-aware upsample",
        };
        let filter = match self.filter {
            LookupFilter::Sampler => "3-D images filtered by the sampler",
            LookupFilter::Texels => "the lattices read as texels and interpolated in the shader",
            LookupFilter::SharedTexels => {
                "the lattices read as texels and interpolated in the shader, each subgroup's lanes fetching the cells around their points together"
            }
        };
        let form = match (&self.apart, &self.lit) {
            (Apart::Compute(_), _) => "; apart, a compute pass",
            (Apart::Fragment(_), None) => "; apart, a fragment pass",
            (Apart::Fragment(_), Some(_)) => "",
        };
        format!("lookup: {resolution}{form}; {filter}")
    }

    /// Fit the lookup's per-view state to view `index` of `views`: at half resolution, its
    /// quarter-size image, made anew when the view's size changed (the images of views past
    /// the last are dropped). Call before the view's lookup in every frame.
    pub fn fit_view(&mut self, gpu: &Gpu, views: &[View], index: usize) -> GpuResult<()> {
        let Some(half) = self.half.as_mut() else {
            return Ok(());
        };
        let view = &views[index];
        let (width, height) = half_size(view.width(), view.height());
        let fits = |image: &Image| (image.width(), image.height()) == (width, height);
        if half.images.len() == views.len() && half.images[index].as_ref().is_some_and(fits) {
            return Ok(());
        }
        // Images of the old size or views may still be in flight.
        gpu.wait_idle()?;
        half.images.resize_with(views.len(), || None);
        half.images[index] = Some(gpu.create_image(&ImageDesc::new_2d(
            "lpv half-resolution light",
            HALF_LIGHT_FORMAT,
            width,
            height,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
        ))?);
        Ok(())
    }

    /// The bindings of `fields`' lattices and of their constants.
    fn field_bindings<'a>(&'a self, fields: &[LookupField<'a>]) -> GpuResult<Vec<Binding<'a>>> {
        if fields.len() != self.fields || field_words(fields) != self.written {
            return Err(GpuError::Setup(format!(
                "the lookup was built for other fields ({} of them, their places, sizes and cell orders as then)",
                self.fields
            )));
        }
        // A one-field lookup binds its lattice in the far slots too; the shader leaves them be.
        let near = [ids::LOOKUP_LATTICE_R, ids::LOOKUP_LATTICE_G, ids::LOOKUP_LATTICE_B];
        let far = [ids::LOOKUP_FAR_LATTICE_R, ids::LOOKUP_FAR_LATTICE_G, ids::LOOKUP_FAR_LATTICE_B];
        let mut bindings = Vec::with_capacity(7);
        for (numbers, field) in [(near, &fields[0]), (far, &fields[fields.len() - 1])] {
            for (c, number) in numbers.into_iter().enumerate() {
                bindings.push(match (&field.lattices, &self.sampler) {
                    (LatticeReads::Images(images), Some(sampler)) => {
                        Binding::sampled(number, &images[c], sampler)
                    }
                    (LatticeReads::Texels(buffers), None) => Binding::texels(number, buffers[c]),
                    _ => {
                        return Err(GpuError::Setup(
                            "the lookup was built to read its fields another way".into(),
                        ));
                    }
                });
            }
        }
        bindings.push(Binding::read(ids::LOOKUP_FIELDS, &self.words));
        Ok(bindings)
    }

    /// At half resolution, record the lookup of `fields` into view `index`'s quarter-size
    /// image and return it (None at full resolution).
    fn record_half<'a>(
        &'a self,
        rec: &mut Recorder,
        view: &View,
        index: usize,
        fields: &[LookupField<'a>],
    ) -> GpuResult<Option<&'a Image>> {
        let Some(half) = &self.half else {
            return Ok(None);
        };
        let image = half.images.get(index).and_then(Option::as_ref).ok_or_else(|| {
            GpuError::Setup(format!("the lookup was not fitted to view {index}"))
        })?;
        let gb = &view.gbuffer;
        let mut bindings = self.field_bindings(fields)?;
        bindings.extend([
            Binding::image_read(ids::LOOKUP_GBUFFER_POSITION, &gb.position),
            Binding::image_read(ids::LOOKUP_GBUFFER_NORMAL, &gb.normal),
        ]);
        rec.raster(&RasterPass {
            name: HALF_LOOKUP,
            pipeline: &half.pipeline,
            bindings: &bindings,
            push: &EyePush::of(view),
            color: &[(image, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(3),
            keep_contents: false,
        })?;
        Ok(Some(image))
    }

    /// Add `fields`' indirect light to view `view`'s HDR image, after its direct lighting.
    pub fn record(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        fields: &[LookupField],
    ) -> GpuResult<()> {
        let index = view;
        let view = &ctx.views[index];
        let gb = &view.gbuffer;
        let mut bindings = vec![
            Binding::image_read(ids::LOOKUP_GBUFFER_POSITION, &gb.position),
            Binding::image_read(ids::LOOKUP_GBUFFER_NORMAL, &gb.normal),
            Binding::image_read(ids::LOOKUP_GBUFFER_ALBEDO, &gb.albedo),
        ];
        let eye = EyePush::of(view);
        let (name, push): (_, &dyn PushConstants) = match self.record_half(rec, view, index, fields)? {
            Some(light) => {
                bindings.push(Binding::image_read(ids::LOOKUP_HALF_LIGHT, light));
                (UPSAMPLE, &eye)
            }
            None => {
                bindings.extend(self.field_bindings(fields)?);
                (LOOKUP, &())
            }
        };
        match &self.apart {
            Apart::Fragment(pipeline) => rec.raster(&RasterPass {
                name,
                pipeline,
                bindings: &bindings,
                push,
                color: &[(&view.hdr, 0, [0.0; 4])],
                depth: Some((&gb.depth, 0)),
                draw: Draw::Vertices(3),
                keep_contents: true,
            }),
            Apart::Compute(pipeline) => {
                bindings.push(Binding::image_write(ids::LOOKUP_HDR, &view.hdr));
                rec.compute(&ComputePass {
                    name,
                    pipeline,
                    bindings: &bindings,
                    push,
                    threads: [view.width(), view.height(), 1],
                })
            }
        }
    }

    /// Draw `direct` (view `view`'s direct lighting) with `fields`' indirect light added, if
    /// this lookup was built for direct lighting of its shape (false: nothing recorded).
    pub fn record_lit(
        &self,
        rec: &mut Recorder,
        (ctx, view): (&FrameContext, usize),
        direct: &DirectDraw,
        fields: &[LookupField],
    ) -> GpuResult<bool> {
        let Some(lit) = self.lit.as_ref().filter(|lit| lit.fits(direct)) else {
            return Ok(false);
        };
        match self.record_half(rec, &ctx.views[view], view, fields)? {
            Some(light) => {
                let half = Binding::image_read(ids::LOOKUP_HALF_LIGHT, light);
                lit.draw(rec, direct, LIT_UPSAMPLE, [half])
            }
            None => lit.draw(rec, direct, LIT_LOOKUP, self.field_bindings(fields)?),
        }
    }
}
