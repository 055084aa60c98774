//! `lightwave`, seed 002 (Robertson 2012, spec 002): a fixed rig of thousands of VPLs on
//! shells around each light, moving rigidly with it, gathered with the thesis's widened 240°
//! lobe and no distance falloff, times one indirect-visibility factor per light from the shadow
//! maps of a few of its VPLs ("accurate": K maps; "integrated": 5 maps and taps interpolated
//! between every pair). No colour bleeding (the VPLs carry no colour) and no inter-reflection:
//! one term of the Neumann series, as the thesis says.
//!
//! vkgi's departures (docs/lightwave.md): the gather runs per vertex as the thesis's, or per
//! pixel (`--lightwave-gather pixel`: free of the tessellation, but measured further from the
//! path tracer on both test scenes); the specular part of eq 4.5 is left out (vkgi's surfaces
//! are Lambertian, as the path tracer's); the thesis's indirect term has no physical unit, so it
//! is scaled by each light's peak intensity and one gain G (1/m²), fitted by least squares to a
//! path-traced image (like the ambient oracle, with the per-pixel gather) unless given.

pub mod bindings;
pub mod cost;
pub mod cpu;
pub mod rig;
pub mod shadows;
pub mod vertex;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};
use crate::gi::{FrameContext, GiMethod, PixelPass};
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, GpuResult, Recorder, Specialization,
};
use crate::gi::shared::oracle::IndirectOracle;
use crate::gpu::GpuError;
use crate::scene::Light;
use crate::scene::bvh::Bvh;
use crate::shaders;
use bindings as ids;
use cost::GATHER;
use rig::Rig;
use shadows::VplShadows;
use vertex::VertexGather;

const SETTINGS: &[Setting] = &[
    Setting::new(
        "lightwave-angle",
        Kind::Int { min: 1, max: 90 },
        "5",
        "Degrees between the rig's rays in azimuth and tilt; divides 90 (the thesis: 5, 10, 30, 45, 90)",
    ),
    Setting::new(
        "lightwave-per-ray",
        Kind::Int {
            min: 1,
            max: rig::MAX_PER_RAY as i64,
        },
        "5",
        "VPLs (shells) along each ray; the sixth shell weighs -0.6, as in the thesis",
    )
    .keys('[', ']', 1.0),
    Setting::new(
        "lightwave-radius",
        Kind::Text,
        "fit",
        "maxDistance, the radius the shells converge to (scene units), or 'fit': half the scene's largest extent",
    ),
    Setting::new(
        "lightwave-gather",
        Kind::Choice(&["vertex", "pixel"]),
        "vertex",
        "Where the gather runs: at every vertex, interpolated across triangles (the thesis's; measured closer to the path tracer, docs/lightwave.md) or at every pixel (free of the mesh's tessellation)",
    )
    .keys('g', 'h', 1.0),
    Setting::new(
        "lightwave-shadows",
        Kind::Choice(&["accurate", "integrated"]),
        "accurate",
        "Indirect shadows: accurate (the mean of --lightwave-shadow-maps VPL maps) or integrated (5 maps, taps interpolated between pairs)",
    )
    .keys(';', '\'', 1.0),
    Setting::new(
        "lightwave-shadow-maps",
        Kind::Int { min: 0, max: 64 },
        "20",
        "VPLs per light with a shadow map in accurate mode (the thesis's K; 0: no indirect shadows)",
    )
    .keys(',', '.', 5.0)
    .sweep(&["0", "20"]),
    Setting::new(
        "lightwave-steps",
        Kind::Int { min: 1, max: 64 },
        "4",
        "Integrated shadows: steps between each pair of maps (1: the 5 maps' mean)",
    )
    .keys('-', '=', 1.0),
    Setting::new(
        "lightwave-shadow-ratio",
        Kind::Float {
            min: 0.25,
            max: 4.0,
        },
        "3",
        "Side of each VPL shadow map as a multiple of the largest view side (the thesis: 3)",
    ),
    Setting::new(
        "lightwave-composite",
        Kind::Choice(&["eq4.9", "shipped", "direct-only", "fake"]),
        "eq4.9",
        "eq4.9: direct + indirect x visibility; shipped: the thesis code's half-strength direct shadows and 0.2/0.8 split; direct-only; fake: eq 5.2 (direct times --lightwave-fake)",
    )
    .keys('c', 'v', 1.0),
    Setting::new(
        "lightwave-fake",
        Kind::Float { min: 0.5, max: 4.0 },
        "1.3",
        "The fake-indirect multiplier m of eq 5.2 (the thesis's best: 1.3)",
    ),
    Setting::new(
        "lightwave-gain",
        Kind::Text,
        "fit",
        "G (1/m²): indirect irradiance = G x light intensity x gather, or 'fit': least squares against a path-traced reference's indirect light",
    ),
    Setting::new(
        "lightwave-fit-spp",
        Kind::Int { min: 1, max: 65536 },
        "16",
        "Samples per pixel of the 64x48 path-traced image the gain fit uses when there is no reference",
    ),
];

pub const METHODS: &[MethodEntry] = &[MethodEntry {
    name: "lightwave",
    description: "seed 002: a fixed rig of VPL shells around each light, gathered per vertex or per pixel, with indirect shadows from a few VPL shadow maps",
    default: false,
    settings: SETTINGS,
    settle_frames: |_| 1,
    profile_axis: None,
    create: |setup, settings| Ok(Box::new(LightWave::new(setup, settings)?)),
}];

crate::push_constants! {
    struct VplsPush {
        angle_deg: u32,
        per_ray: u32,
        radius: f32,
        per_light: u32,
        light_count: u32,
    }
}

crate::push_constants! {
    struct GatherPush {
        size: [u32; 2],
        fake: f32,
        gain: f32,
    }
}

/// How the indirect visibility is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowMode {
    /// No VPL shadow maps: visibility 1.
    None,
    /// The mean of K maps of pseudo-random VPLs.
    Accurate,
    /// Five fixed maps, taps interpolated between every pair.
    Integrated,
}

impl ShadowMode {
    fn id(self) -> u32 {
        match self {
            ShadowMode::None => ids::SHADOWS_NONE,
            ShadowMode::Accurate => ids::SHADOWS_ACCURATE,
            ShadowMode::Integrated => ids::SHADOWS_INTEGRATED,
        }
    }
}

/// The method's settings, parsed and checked.
#[derive(Clone, Debug)]
pub struct LightWaveSettings {
    pub rig: Rig,
    /// Gather at every vertex (the thesis) rather than at every pixel.
    pub per_vertex: bool,
    pub shadows: ShadowMode,
    /// Which VPLs of each rig have a shadow map.
    pub shadow_set: Vec<u32>,
    pub steps: u32,
    pub shadow_ratio: f32,
    pub composite: &'static str,
    pub fake: f32,
    /// The gain G when given (None: fit it).
    pub gain: Option<f64>,
    pub fit_spp: u32,
}

impl LightWaveSettings {
    pub fn parse(settings: &Settings, scene: &crate::scene::Scene) -> Result<Self, InputError> {
        let radius = match settings.text("lightwave-radius")? {
            t if t.eq_ignore_ascii_case("fit") => {
                0.5 * f64::from((scene.bounds_max - scene.bounds_min).max_element())
            }
            t => positive("lightwave-radius", t)?,
        };
        let rig = Rig::new(
            settings.u32("lightwave-angle")?,
            settings.u32("lightwave-per-ray")?,
            radius,
        )?;
        let composite = match settings.text("lightwave-composite")? {
            "shipped" => "shipped",
            "direct-only" => "direct-only",
            "fake" => "fake",
            _ => "eq4.9",
        };
        // direct-only and fake use no indirect light: like the thesis's builds of them, they
        // render no VPL shadow map, gather nothing and fit no gain.
        let indirect = adds_indirect(composite);
        let maps = settings.u32("lightwave-shadow-maps")?;
        let (shadows, shadow_set) = match settings.text("lightwave-shadows")? {
            _ if !indirect => (ShadowMode::None, Vec::new()),
            "integrated" => (ShadowMode::Integrated, rig.integrated_shadow_set().to_vec()),
            _ if maps == 0 => (ShadowMode::None, Vec::new()),
            _ => (ShadowMode::Accurate, rig.accurate_shadow_set(maps)),
        };
        let gain = match settings.text("lightwave-gain")? {
            t if t.eq_ignore_ascii_case("fit") => None,
            t => Some(non_negative("lightwave-gain", t)?),
        };
        let gain = if indirect { gain } else { Some(0.0) };
        Ok(LightWaveSettings {
            rig,
            per_vertex: indirect && settings.text("lightwave-gather")? == "vertex",
            shadows,
            shadow_set,
            steps: settings.u32("lightwave-steps")?,
            shadow_ratio: settings.float("lightwave-shadow-ratio")? as f32,
            composite,
            fake: settings.float("lightwave-fake")? as f32,
            gain,
            fit_spp: settings.u32("lightwave-fit-spp")?,
        })
    }

    /// The composite adds the gathered indirect light (eq4.9, shipped).
    pub fn uses_indirect(&self) -> bool {
        adds_indirect(self.composite)
    }

    fn composite_id(&self) -> u32 {
        match self.composite {
            "shipped" => ids::COMPOSITE_SHIPPED,
            "direct-only" => ids::COMPOSITE_DIRECT_ONLY,
            "fake" => ids::COMPOSITE_FAKE,
            _ => ids::COMPOSITE_EQ_4_9,
        }
    }
}

/// The gather's constants (composite.glsl): what the settings fix, so that lavapipe, which runs
/// both sides of every branch, runs only the composite and the visibility chosen.
fn gather_specialization(s: &LightWaveSettings, light_count: u32) -> Specialization {
    Specialization::new()
        .with_u32(0, light_count)
        .with_u32(1, s.rig.count())
        .with_u32(2, s.shadows.id())
        .with_u32(3, s.shadow_set.len() as u32)
        .with_u32(4, s.steps)
        .with_u32(5, s.composite_id())
}

/// Whether `composite` adds the gathered indirect light.
fn adds_indirect(composite: &str) -> bool {
    matches!(composite, "eq4.9" | "shipped")
}

/// `text` as a finite number > 0 (`name` names the flag in the error).
fn positive(name: &str, text: &str) -> Result<f64, InputError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= f64::from(crate::scene::MAX_COORDINATE) => Ok(v),
        _ => Err(InputError::new(format!(
            "--{name} {text}: expected 'fit' or a number in (0, {:e}]",
            crate::scene::MAX_COORDINATE
        ))),
    }
}

/// `text` as a finite number ≥ 0.
fn non_negative(name: &str, text: &str) -> Result<f64, InputError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=1e30).contains(&v) => Ok(v),
        _ => Err(InputError::new(format!(
            "--{name} {text}: expected 'fit' or a number in [0, 1e30]"
        ))),
    }
}

/// Where G comes from.
enum GainSource {
    /// Given, or fitted to the caller's reference (which does not follow moved lights).
    Fixed(&'static str),
    /// Fitted to a path-traced image of its own, refitted when the lights change.
    Fit(Box<(IndirectOracle, Bvh)>),
}

pub struct LightWave {
    settings: LightWaveSettings,
    /// G (1/m²).
    pub gain: f64,
    gain_source: GainSource,
    /// Lights the rasteriser draws (the rigs' count).
    light_count: u32,
    vpls: Buffer,
    vpl_pipeline: ComputePipeline,
    gather_pipeline: ComputePipeline,
    /// The per-vertex gather (None: per pixel).
    vertex: Option<VertexGather>,
    shadows: VplShadows,
}

impl LightWave {
    pub fn new(setup: &Setup, settings: &Settings) -> anyhow::Result<LightWave> {
        LightWave::with(setup, LightWaveSettings::parse(settings, setup.scene)?)
    }

    /// The method with settings already parsed (tests use this to pick the shadow set).
    pub fn with(setup: &Setup, s: LightWaveSettings) -> anyhow::Result<LightWave> {
        let gpu = setup.gpu;
        let scene = setup.scene;
        let lights = scene.raster_lights();
        let light_count = lights.len() as u32;
        let vpl_bytes = u64::from(light_count.max(1)) * u64::from(s.rig.count()) * 32;
        crate::render::targets::check_buffer(
            gpu,
            &format!("LightWave's {} VPLs", light_count * s.rig.count()),
            vpl_bytes,
        )?;
        // The BVH only serves the fit: a given gain skips building it.
        let (gain, gain_source) = match (s.gain, setup.reference) {
            (Some(g), _) if !s.uses_indirect() => (g, GainSource::Fixed("unused by the composite")),
            (Some(g), _) => (g, GainSource::Fixed("given")),
            (None, Some(reference)) => (
                cpu::fit_gain(
                    scene,
                    &Bvh::build(&scene.mesh),
                    &lights,
                    &s.rig,
                    &s.shadow_set,
                    &reference.indirect,
                ),
                GainSource::Fixed("fitted to the caller's reference"),
            ),
            (None, None) => {
                let bvh = Bvh::build(&scene.mesh);
                let what = "fitting LightWave's gain to a path-traced image";
                (setup.progress)(what, 0.0);
                let mut oracle = IndirectOracle::new(gpu, scene, s.fit_spp)?;
                let truth = oracle.render(gpu)?;
                let gain = cpu::fit_gain(scene, &bvh, &lights, &s.rig, &s.shadow_set, &truth);
                (setup.progress)(what, 1.0);
                (gain, GainSource::Fit(Box::new((oracle, bvh))))
            }
        };
        let none = Specialization::new();
        Ok(LightWave {
            vpls: gpu.create_buffer(&BufferDesc::storage_texels("lightwave vpls", vpl_bytes))?,
            vpl_pipeline: ComputePipeline::new(
                gpu,
                "lightwave vpls",
                shaders::GI_LIGHTWAVE_VPLS_COMP,
                &none,
            )?,
            gather_pipeline: ComputePipeline::new(
                gpu,
                GATHER,
                if s.per_vertex {
                    shaders::GI_LIGHTWAVE_GATHER_VERTEX_COMP
                } else {
                    shaders::GI_LIGHTWAVE_GATHER_COMP
                },
                &gather_specialization(&s, light_count),
            )?,
            vertex: s
                .per_vertex
                .then(|| VertexGather::new(gpu, scene, light_count))
                .transpose()?,
            shadows: VplShadows::new(gpu, scene, &lights, s.shadow_set.clone(), s.shadow_ratio)?,
            light_count,
            gain,
            gain_source,
            settings: s,
        })
    }
}

impl LightWave {
    /// The VPL buffer as this frame's rigs left it: per VPL, (position, weight) and
    /// (direction, light index).
    pub fn read_vpls(&self, gpu: &crate::gpu::Gpu) -> GpuResult<Vec<[f32; 8]>> {
        let bytes = gpu.read_buffer(&self.vpls)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 8]>(&bytes).to_vec())
    }

    /// The per-vertex gather's values (per vertex, per light: front, back), or None per pixel.
    pub fn read_vertex_values(&self, gpu: &crate::gpu::Gpu) -> GpuResult<Option<Vec<[f32; 2]>>> {
        self.vertex.as_ref().map(|v| v.read_values(gpu)).transpose()
    }
}

impl LightWave {
    /// Fit G again to the path-traced image of the moved lights (`lights`: the frame's own,
    /// `raster_lights` with the area-light samples).
    fn refit(&mut self, gpu: &crate::gpu::Gpu, lights: &[Light], raster: &[Light]) -> anyhow::Result<()> {
        let GainSource::Fit(fit) = &mut self.gain_source else {
            return Ok(());
        };
        let (oracle, bvh) = &mut **fit;
        oracle.set_lights(gpu, lights)?;
        let truth = oracle.render(gpu)?;
        let s = &self.settings;
        self.gain = cpu::fit_gain(&oracle.scene, bvh, raster, &s.rig, &s.shadow_set, &truth);
        Ok(())
    }
}

impl GiMethod for LightWave {
    fn name(&self) -> &'static str {
        "lightwave"
    }

    /// The rigs from this frame's lights, then the VPL shadow maps (and G refitted when the
    /// lights changed and G is fitted to an image of its own).
    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        if ctx.frame > 0 && ctx.changes.lights {
            self.refit(rec.gpu(), ctx.lights, ctx.raster_lights)
                .map_err(|e| GpuError::Setup(format!("refitting LightWave's gain: {e:#}")))?;
        }
        let rig = &self.settings.rig;
        let push = VplsPush {
            angle_deg: rig.angle_deg,
            per_ray: rig.per_ray,
            radius: rig.radius as f32,
            per_light: rig.count(),
            light_count: self.light_count,
        };
        rec.compute(&ComputePass {
            name: "lightwave vpls",
            pipeline: &self.vpl_pipeline,
            bindings: &[
                Binding::read(ids::VPLS_LIGHTS, &ctx.scene.lights),
                Binding::write(ids::VPLS_OUT, &self.vpls),
            ],
            push: &push,
            threads: [rig.count() * self.light_count, 1, 1],
        })?;
        if let Some(vertex) = &mut self.vertex {
            vertex.record(rec, ctx, &self.vpls, rig.count())?;
        }
        self.shadows.record(rec, ctx, rig)
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, index: usize) -> GpuResult<()> {
        let view = &ctx.views[index];
        let Some(vpl_shadow_map) = self.shadows.image() else {
            return Ok(());
        };
        if let Some(vertex) = &self.vertex {
            vertex.record_view(rec, ctx, index)?;
        }
        let s = &self.settings;
        let push = GatherPush {
            size: [view.width(), view.height()],
            fake: s.fake,
            gain: self.gain as f32,
        };
        let g = &view.gbuffer;
        let mut bindings = vec![
                Binding::image_read(ids::GATHER_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::GATHER_GBUFFER_NORMAL, &g.normal),
                Binding::image_read(ids::GATHER_GBUFFER_ALBEDO, &g.albedo),
                Binding::texels(ids::GATHER_VPLS, &self.vpls),
                Binding::read(ids::GATHER_LIGHTS, &ctx.scene.lights),
                Binding::sampled(
                    ids::GATHER_SCENE_SHADOW_MAP,
                    ctx.shadow_map,
                    ctx.shadow_sampler,
                ),
                Binding::read(ids::GATHER_SCENE_SHADOW_VIEWS, &ctx.scene.shadow_views),
                Binding::sampled(
                    ids::GATHER_VPL_SHADOW_MAP,
                    vpl_shadow_map,
                    ctx.shadow_sampler,
                ),
                Binding::texels(ids::GATHER_VPL_SHADOW_VIEWS, self.shadows.views()),
                Binding::image_write(ids::GATHER_HDR, &view.hdr),
            ];
        if let Some(vertex) = &self.vertex {
            bindings.extend(vertex.bindings(ctx, index));
        }
        rec.compute(&ComputePass {
            name: GATHER,
            pipeline: &self.gather_pipeline,
            bindings: &bindings,
            push: &push,
            threads: [view.width(), view.height(), 1],
        })
    }

    fn pixel_passes(&self) -> Vec<PixelPass> {
        cost::gather_pass(&self.settings, self.light_count, self.shadows.per_light())
            .into_iter()
            .collect()
    }

    fn describe(&self) -> Vec<String> {
        let s = &self.settings;
        let rig = &s.rig;
        let source = match &self.gain_source {
            GainSource::Fixed(how) => how.to_string(),
            GainSource::Fit(fit) => format!("fitted to {}", fit.0.describe()),
        };
        let shadows = match s.shadows {
            ShadowMode::None => "no indirect shadows".to_string(),
            ShadowMode::Accurate => format!("accurate indirect shadows, {} maps", s.shadow_set.len()),
            ShadowMode::Integrated => {
                format!("integrated indirect shadows, 5 maps, {} steps", s.steps)
            }
        };
        let side = match self.shadows.clamped_from {
            Some(wanted) => format!(
                "{0}x{0} (clamped from {wanted} by the memory limit)",
                self.shadows.side
            ),
            None => format!("{0}x{0}", self.shadows.side),
        };
        vec![
            format!(
                "lightwave: {} VPLs per light ({}° between rays, {} per ray, radius {:.4}), {} light(s), gathered per {}",
                rig.count(),
                rig.angle_deg,
                rig.per_ray,
                rig.radius,
                self.light_count,
                if s.per_vertex { "vertex" } else { "pixel" }
            ),
            format!(
                "lightwave: {shadows}, maps {side} (ratio {}), composite {}",
                s.shadow_ratio, s.composite
            ),
            format!("lightwave: gain G = {:.6e} /m², {source}", self.gain),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_and_gain_take_fit_or_a_number() {
        assert!(positive("x", "4").is_ok());
        for bad in ["0", "-1", "nan", "inf", "1e40", "four"] {
            assert!(positive("x", bad).is_err(), "{bad}");
        }
        assert_eq!(non_negative("x", "0").ok(), Some(0.0));
        for bad in ["-1", "nan", "1e31", ""] {
            assert!(non_negative("x", bad).is_err(), "{bad}");
        }
    }
}
