//! `ambient`, the baseline every method must beat: indirect light = albedo × E / π with one
//! constant irradiance E per colour channel, either given (`--ambient-irradiance R,G,B`) or
//! fitted by least squares to a path-traced image of the scene's indirect light (an oracle: the
//! best any constant can do). The fit uses the caller's reference when there is one (the
//! report's), else a small path-traced one of its own, redone whenever the lights change.
//!
//! Where the frame's direct lighting is a fragment pass, the term is drawn inside it
//! (`ambient/lit.{vert,frag}`: the G-buffer read once, the HDR image written once, the
//! background skipped); else, or when the frame asks (`FrameOptions::lookup_apart`), as a
//! compute pass of its own after it (`ambient/lookup.comp`).

pub mod bindings;
pub mod fit;

use glam::Vec3;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};
use crate::gi::{FrameContext, GiMethod, PixelPass};
use crate::gpu::{
    Binding, Buffer, ComputePass, ComputePipeline, Gpu, GpuError, GpuResult, Recorder,
    Specialization,
};
use crate::gi::shared::oracle::{self, IndirectOracle};
use crate::render::full_screen::FullScreenShaders;
use crate::render::passes::{DirectDraw, LitPipeline};
use crate::scene::bvh::Bvh;
use crate::shaders;
use bindings as ids;

/// Largest irradiance a user may give per channel.
const MAX_IRRADIANCE: f32 = 1e30;

/// The term as a pass of its own, and drawn inside direct lighting (their names in the profile).
const AMBIENT: &str = "ambient";
const LIT_AMBIENT: &str = "direct lighting + ambient";

/// Flops of the term at a pixel: albedo times E times 1/π, added to what is there.
const FLOPS_PER_PIXEL: f64 = 3.0 + 3.0 + 3.0;
/// What the pass of its own moves at a covered pixel at the ideal: whether a surface covers it
/// (the depth, 4 B), the albedo (8 B), the HDR pixel read and written (16 B each); at a
/// background pixel only the depth. Inside direct lighting it adds no bytes to direct
/// lighting's (which reads the albedo already) and nothing at a background pixel.
const BYTES_PER_PIXEL: f64 = 4.0 + 8.0 + 16.0 + 16.0;
const BACKGROUND_BYTES: f64 = 4.0;

const SETTINGS: &[Setting] = &[
    Setting::new(
        "ambient-irradiance",
        Kind::Text,
        "fit",
        "The constant irradiance E as R,G,B (W/m²), or 'fit': least squares against a path-traced reference's indirect light",
    ),
    Setting::new(
        "ambient-spp",
        Kind::Int { min: 1, max: 65536 },
        "16",
        "Samples per pixel of the 64x48 path-traced image the fit uses when there is no reference",
    ),
];

pub const METHODS: &[MethodEntry] = &[MethodEntry {
    name: "ambient",
    description: "the baseline: albedo times one constant irradiance per channel, fitted to the path tracer (an oracle) or given",
    default: false,
    settings: SETTINGS,
    settle_frames: |_| 1,
    profile_axis: None,
    create: |setup, settings| Ok(Box::new(Ambient::new(setup, settings)?)),
}];

crate::push_constants! {
    struct AmbientPush {
        irradiance: [f32; 4],
        size: [u32; 2],
    }
}

/// How E is found.
enum Source {
    Given,
    /// Fitted to a path-traced image of the scene camera, refitted when the lights change.
    Fit(Box<Fitter>),
}

/// What a refit needs: the path-traced image of the scene's indirect light and the albedo each
/// of its pixels sees.
struct Fitter {
    oracle: IndirectOracle,
    albedo: Vec<[f32; 3]>,
}

impl Fitter {
    fn fit(&mut self, gpu: &Gpu) -> anyhow::Result<Vec3> {
        Ok(fit::fit_irradiance(&self.albedo, &self.oracle.render(gpu)?))
    }
}

pub struct Ambient {
    /// Irradiance per channel (W/m²).
    pub irradiance: Vec3,
    source: Source,
    /// The term as a compute pass of its own.
    pipeline: ComputePipeline,
    /// Direct lighting with the term, for direct lighting of this shape (None: direct lighting
    /// is a compute pass).
    lit: Option<LitPipeline>,
    /// E as the lit pass's vertex shader reads it (rgb, w 0), rewritten after a refit.
    irradiance_words: Buffer,
}

impl Ambient {
    pub fn new(setup: &Setup, settings: &Settings) -> anyhow::Result<Ambient> {
        let gpu = setup.gpu;
        let (irradiance, source) = irradiance_source(setup, settings)?;
        let pipeline = ComputePipeline::new(
            gpu,
            AMBIENT,
            shaders::GI_AMBIENT_LOOKUP_COMP,
            &Specialization::new(),
        )?;
        let shaders = FullScreenShaders {
            vertex: shaders::GI_AMBIENT_LIT_VERT,
            fragment: shaders::GI_AMBIENT_LIT_FRAG,
        };
        let lit = LitPipeline::new(gpu, setup.scene, LIT_AMBIENT, shaders, |spec| spec)?;
        let irradiance_words = gpu.upload_storage("ambient irradiance", &words(irradiance))?;
        Ok(Ambient {
            irradiance,
            source,
            pipeline,
            lit,
            irradiance_words,
        })
    }
}

/// E, given or fitted, and how it is found from then on.
fn irradiance_source(setup: &Setup, settings: &Settings) -> anyhow::Result<(Vec3, Source)> {
    let text = settings.text("ambient-irradiance")?;
    if !text.eq_ignore_ascii_case("fit") {
        return Ok((parse_irradiance(text)?, Source::Given));
    }
    let bvh = Bvh::build(&setup.scene.mesh);
    if let Some(reference) = setup.reference {
        let truth = &reference.indirect;
        let albedo = fit::albedo_image(setup.scene, &bvh, truth.width, truth.height);
        return Ok((fit::fit_irradiance(&albedo, truth), Source::Given));
    }
    (setup.progress)("fitting the ambient term to a path-traced image", 0.0);
    let (width, height) = oracle::SIZE;
    let mut fitter = Fitter {
        albedo: fit::albedo_image(setup.scene, &bvh, width, height),
        oracle: IndirectOracle::new(setup.gpu, setup.scene, settings.u32("ambient-spp")?)?,
    };
    let irradiance = fitter.fit(setup.gpu)?;
    (setup.progress)("fitting the ambient term to a path-traced image", 1.0);
    Ok((irradiance, Source::Fit(Box::new(fitter))))
}

/// E as the shaders read it: rgb, w 0.
fn words(irradiance: Vec3) -> Vec<u8> {
    bytemuck::cast_slice(&irradiance.extend(0.0).to_array()).to_vec()
}

/// "R,G,B" as a finite, non-negative irradiance.
fn parse_irradiance(text: &str) -> Result<Vec3, InputError> {
    let bad = || {
        InputError::new(format!(
            "--ambient-irradiance {text}: expected 'fit' or R,G,B with three numbers in [0, {MAX_IRRADIANCE:e}]"
        ))
    };
    let values: Vec<f32> = text
        .split(',')
        .map(|v| v.trim().parse::<f32>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    match values[..] {
        [r, g, b] if values.iter().all(|v| v.is_finite() && (0.0..=MAX_IRRADIANCE).contains(v)) => {
            Ok(Vec3::new(r, g, b))
        }
        _ => Err(bad()),
    }
}

impl GiMethod for Ambient {
    fn name(&self) -> &'static str {
        "ambient"
    }

    /// Refit when the lights changed (the first frame's lights are those of the set-up fit).
    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        let Source::Fit(fitter) = &mut self.source else {
            return Ok(());
        };
        if ctx.frame == 0 || !ctx.changes.lights {
            return Ok(());
        }
        fitter.oracle.set_lights(rec.gpu(), ctx.lights)?;
        let irradiance = fitter
            .fit(rec.gpu())
            .map_err(|e| GpuError::Setup(format!("refitting the ambient term: {e:#}")))?;
        // Lights said to change may leave E as it was (the profile's frames).
        if irradiance != self.irradiance {
            self.irradiance = irradiance;
            rec.update_buffer("ambient irradiance", &self.irradiance_words, &words(irradiance));
        }
        Ok(())
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        let view = &ctx.views[view];
        let push = AmbientPush {
            irradiance: self.irradiance.extend(0.0).to_array(),
            size: [view.width(), view.height()],
        };
        rec.compute(&ComputePass {
            name: AMBIENT,
            pipeline: &self.pipeline,
            bindings: &[
                Binding::image_read(ids::AMBIENT_GBUFFER_POSITION, &view.gbuffer.position),
                Binding::image_read(ids::AMBIENT_GBUFFER_ALBEDO, &view.gbuffer.albedo),
                Binding::image_write(ids::AMBIENT_HDR, &view.hdr),
            ],
            push: &push,
            threads: [view.width(), view.height(), 1],
        })
    }

    fn record_lit_lookup(
        &self,
        rec: &mut Recorder,
        _ctx: &FrameContext,
        _view: usize,
        direct: &DirectDraw,
    ) -> GpuResult<bool> {
        let irradiance = Binding::read(ids::AMBIENT_IRRADIANCE, &self.irradiance_words);
        let lit = self.lit.as_ref();
        lit.map_or(Ok(false), |lit| lit.draw(rec, direct, LIT_AMBIENT, [irradiance]))
    }

    fn pixel_passes(&self) -> Vec<PixelPass> {
        vec![
            PixelPass {
                pass: AMBIENT,
                bytes_per_pixel: BYTES_PER_PIXEL,
                flops_per_pixel: FLOPS_PER_PIXEL,
                with_direct_lighting: false,
                background_bytes: Some(BACKGROUND_BYTES),
            },
            PixelPass {
                pass: LIT_AMBIENT,
                bytes_per_pixel: 0.0,
                flops_per_pixel: FLOPS_PER_PIXEL,
                with_direct_lighting: true,
                background_bytes: Some(0.0),
            },
        ]
    }

    fn describe(&self) -> Vec<String> {
        let source = match &self.source {
            Source::Given => "given or fitted to the caller's reference".to_string(),
            Source::Fit(f) => format!("fitted to {}", f.oracle.describe()),
        };
        let form = match self.lit {
            Some(_) => "drawn inside direct lighting (apart, a compute pass)",
            None => "a compute pass after direct lighting",
        };
        vec![format!(
            "ambient: irradiance E = ({:.6}, {:.6}, {:.6}) W/m², {source}; {form}",
            self.irradiance.x, self.irradiance.y, self.irradiance.z
        )]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_irradiance_must_be_three_finite_non_negative_numbers() {
        assert_eq!(parse_irradiance("1, 2,3").ok(), Some(Vec3::new(1.0, 2.0, 3.0)));
        for bad in ["1,2", "1,2,3,4", "a,b,c", "NaN,1,1", "-1,0,0", "1e39,0,0", ""] {
            assert!(parse_irradiance(bad).is_err(), "{bad}");
        }
    }
}
