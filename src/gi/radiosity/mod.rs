//! `radiosity`, seed 004 (Bozalina 2011, spec 004): progressive-refinement radiosity on the
//! GPU. The scene's polygons (patches) are split into texel elements on each side light can
//! reach; every shot picks the surface of most unshot power on the GPU, shoots its unshot
//! radiosity from blocks of its texels through a hemisphere item buffer (the thesis's one-pass
//! stereographic projection of a subdivided mesh, or a hemicube), and adds the
//! disc-approximation form factor's share to every visible element. Punctual lights shoot
//! first, as point emitters. The display adds the elements' indirect irradiance, interpolated
//! across each polygon, plus the ambient term still to arrive (§4.1.6); the rasteriser draws
//! the direct light. Where direct lighting is a fragment pass (lavapipe) the display is drawn
//! inside it (`radiosity/lit_display.frag`: the G-buffer read once, the HDR image written once,
//! the background skipped); elsewhere, or when the frame asks (`FrameOptions::lookup_apart`), it
//! is a compute pass of its own (`radiosity/display.comp`).
//!
//! Three modes (`--radiosity-mode`): `pr`, progressive refinement; `id`, importance-driven
//! (importance shot from the user's camera weights the shooter choice, §5); `pd`,
//! perspective-driven (as `id`, and surfaces out of the simulated view, which widens by 5° every
//! `--pd-decay-shots` shots, wait in a stored table until they come into view, §6).

pub mod bindings;
pub mod camera;
pub mod cpu;
pub mod elements;
pub mod solver;
pub mod table;

use std::time::Instant;

use ash::vk;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};
use crate::gi::shared::triangle_ids::TriangleIds;
use crate::gi::{Convergence, FrameContext, GiMethod, PixelPass};
use crate::gpu::{
    Binding, Buffer, ComputePass, ComputePipeline, Gpu, GpuResult, Recorder, Specialization,
};
use crate::render::full_screen::FullScreenShaders;
use crate::render::passes::{DirectDraw, LitPipeline};
use crate::shaders;
use bindings as ids;
use elements::{Density, Elements};
use camera::{CameraView, SimulatedView};
use solver::{Mode, Solver, SolverOptions};

const SETTINGS: &[Setting] = &[
    Setting::new(
        "radiosity-mode",
        Kind::Choice(Mode::NAMES),
        "pr",
        "pr: progressive refinement, the most unshot power first; id: importance-driven, weighted by importance from the camera; pd: perspective-driven, id with receivers limited to a simulated view that widens",
    )
    .keys('[', ']', 1.0),
    Setting::new(
        "pd-decay-shots",
        Kind::Int { min: 1, max: 1_000_000 },
        "40",
        "pd: shots between the simulated view's 5-degree widenings (the thesis's decay constant, counted in shots so renders repeat)",
    )
    .keys(',', '.', 10.0),
    Setting::new(
        "elements",
        Kind::Text,
        "4096",
        "Receiving elements: a total budget over the reachable surfaces (e.g. 4096), or a density per unit area (e.g. 2000/area)",
    ),
    Setting::new(
        "hemisphere",
        Kind::Choice(&["stereographic", "hemicube"]),
        "stereographic",
        "The item buffer's projection: the thesis's one-pass stereographic projection of a subdivided mesh, or five hemicube faces",
    ),
    Setting::new(
        "item-buffer",
        Kind::Int { min: 16, max: 4096 },
        "256",
        "Side of the hemisphere item buffer in pixels (of each hemicube face)",
    ),
    Setting::new(
        "item-mesh-level",
        Kind::Int { min: 0, max: 4 },
        "2",
        "1-to-4 subdivisions of the item-buffer mesh (stereographic edges bend; the thesis: 2)",
    ),
    Setting::new(
        "shooting-locations",
        Kind::Int { min: 1, max: 1024 },
        "16",
        "Most shooting locations per shot: a surface shoots from blocks of 2^n x 2^n texels, n as small as keeps within this",
    ),
    Setting::new(
        "radiosity-shots",
        Kind::Int { min: 0, max: 100_000 },
        "8",
        "Shots per frame (0: as many as --budget-ms allows; a fixed count keeps renders reproducible)",
    ),
    Setting::new(
        "budget-ms",
        Kind::Float {
            min: 1.0,
            max: 100_000.0,
        },
        "100",
        "Frame time the shots per frame adapt to when --radiosity-shots is 0",
    )
    .keys('-', '=', 10.0),
    Setting::new(
        "radiosity-epsilon",
        Kind::Float { min: 0.0, max: 1.0 },
        "1e-4",
        "Converged when no surface has more than this fraction of the most unshot power there was",
    ),
    Setting::new(
        "radiosity-ambient",
        Kind::Choice(&["on", "off"]),
        "on",
        "Show the ambient term of light still unshot (display only, never shot)",
    ),
];

/// Shots `render` and `report` run by default: the Cornell boxes converge (ε 1e-4) in 120–200.
const SETTLE_SHOTS: u32 = 240;
/// Frames when the shots per frame follow the time budget.
const SETTLE_FRAMES_BUDGETED: u32 = 200;

pub const METHODS: &[MethodEntry] = &[MethodEntry {
    name: "radiosity",
    description: "seed 004: progressive-refinement radiosity on texel elements, shot through a stereographic (or hemicube) item buffer, with the ambient term",
    default: false,
    settings: SETTINGS,
    settle_frames: |settings| match settings.u32("radiosity-shots") {
        Ok(0) | Err(_) => SETTLE_FRAMES_BUDGETED,
        Ok(shots) => SETTLE_SHOTS.div_ceil(shots).max(1),
    },
    profile_axis: None,
    create: |setup, settings| Ok(Box::new(Radiosity::new(setup, settings)?)),
}];

/// The display as a pass of its own, and drawn inside direct lighting (their names in the
/// profile).
const DISPLAY: &str = "radiosity display";
const LIT_DISPLAY: &str = "direct lighting + radiosity display";

/// What the display must move and compute at a covered pixel at the ideal. Apart: the pixel's
/// position (16 B) and triangle (4 B), its albedo (8 B), the HDR pixel read and written (16 B
/// each); at a background pixel whether a surface covers it (the depth, 4 B). Inside direct
/// lighting, which reads the position and albedo already: the triangle. The surfaces' records
/// and the elements' irradiance serve many pixels (at the ideal, read once a frame). Flops: the
/// side facing the eye 8, the grid texel and its fractions 21, four corners' weights and
/// weighted sums 40, the normalisation and the ambient term 6, albedo / pi times it added 9.
const DISPLAY_BYTES_PER_PIXEL: f64 = 16.0 + 4.0 + 8.0 + 16.0 + 16.0;
const LIT_DISPLAY_BYTES_PER_PIXEL: f64 = 4.0;
const DISPLAY_BACKGROUND_BYTES: f64 = 4.0;
const DISPLAY_FLOPS_PER_PIXEL: f64 = 8.0 + 21.0 + 40.0 + 6.0 + 9.0;

crate::push_constants! {
    struct DisplayPush {
        eye: [f32; 4],
        size: [u32; 2],
        ambient: u32,
    }
}

/// Per mesh triangle, what the display needs to find the surface a pixel shows, as two RGBA32UI
/// texels (radiosity/display.glsl): its patch's normal (as float bits) and the surface of the
/// patch's front side, then the surface of its back side (`NO_SURFACE` where light never
/// reaches a side).
fn triangle_sides(gpu: &Gpu, elements: &Elements) -> anyhow::Result<Buffer> {
    let count = elements.triangle_patch.len();
    let bytes = count.max(1) as u64 * 32;
    crate::render::targets::check_texel_buffer(gpu, "radiosity's triangle sides", bytes)?;
    Ok(gpu.upload_texel_items(
        "radiosity triangle sides",
        count,
        vk::Format::R32G32B32A32_UINT,
        |t| {
            let Some(&patch) = elements.triangle_patch.get(t) else {
                return [[0u32; 4]; 2];
            };
            let n = elements.patches[patch as usize].normal;
            let [front, back] = elements.patch_surfaces[patch as usize];
            [
                [n.x.to_bits(), n.y.to_bits(), n.z.to_bits(), front],
                [back, 0, 0, 0],
            ]
        },
    )?)
}

/// The method's settings, parsed and checked.
#[derive(Clone, Debug)]
pub struct RadiositySettings {
    pub density: Density,
    pub decay_shots: u32,
    pub solver: SolverOptions,
    /// Shots per frame; None: from the budget.
    pub shots: Option<u32>,
    pub budget_ms: f64,
    pub ambient: bool,
}

impl RadiositySettings {
    pub fn parse(settings: &Settings) -> Result<Self, InputError> {
        let shots = settings.u32("radiosity-shots")?;
        let mode = settings.text("radiosity-mode")?;
        Ok(RadiositySettings {
            density: parse_density(settings.text("elements")?)?,
            decay_shots: settings.u32("pd-decay-shots")?,
            solver: SolverOptions {
                mode: Mode::parse(mode).ok_or_else(|| {
                    InputError::new(format!("--radiosity-mode {mode}: not one of pr, id, pd"))
                })?,
                hemicube: settings.text("hemisphere")? == "hemicube",
                resolution: settings.u32("item-buffer")?,
                item_level: settings.u32("item-mesh-level")?,
                locations: settings.u32("shooting-locations")?,
                epsilon: settings.float("radiosity-epsilon")? as f32,
            },
            shots: (shots > 0).then_some(shots),
            budget_ms: settings.float("budget-ms")?,
            ambient: settings.text("radiosity-ambient")? == "on",
        })
    }
}

/// Largest element budget: 16M texels (a quarter of a GiB per vec4 buffer).
const MAX_ELEMENTS: f64 = 16.0 * 1024.0 * 1024.0;

fn parse_density(text: &str) -> Result<Density, InputError> {
    let bad = || {
        InputError::new(format!(
            "--elements {text}: expected a whole number of elements (1 to {MAX_ELEMENTS}) or a density per unit area such as 2000/area"
        ))
    };
    let (number, per_area) = match text.trim().strip_suffix("/area") {
        Some(n) => (n, true),
        None => (text.trim(), false),
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    if !value.is_finite() || value <= 0.0 {
        return Err(bad());
    }
    if per_area {
        return Ok(Density::PerArea(value));
    }
    if value.fract() != 0.0 || value > MAX_ELEMENTS {
        return Err(bad());
    }
    Ok(Density::Budget(value as u32))
}

pub struct Radiosity {
    settings: RadiositySettings,
    pub solver: Solver,
    triangle_ids: TriangleIds,
    /// The display as a compute pass of its own.
    display: ComputePipeline,
    /// Direct lighting with the display, for direct lighting of this shape (None: direct
    /// lighting is a compute pass).
    lit_display: Option<LitPipeline>,
    /// Per mesh triangle, its patch's normal and the surfaces of its two sides
    /// (`triangle_sides`).
    triangle_sides: Buffer,
    /// pd's simulated field of view, and whether it changed since the surfaces in it were last
    /// marked.
    simulated: SimulatedView,
    simulated_changed: bool,
    /// Shots the next frame records when they follow the budget.
    budgeted_shots: f64,
    last_frame: Option<Instant>,
}

impl Radiosity {
    pub fn new(setup: &Setup, settings: &Settings) -> anyhow::Result<Radiosity> {
        Radiosity::with(setup, RadiositySettings::parse(settings)?)
    }

    pub fn with(setup: &Setup, settings: RadiositySettings) -> anyhow::Result<Radiosity> {
        let gpu = setup.gpu;
        let scene = setup.scene;
        let elements = Elements::bake(scene, settings.density, &|f| {
            (setup.progress)("baking radiosity elements", f)
        });
        if elements.surfaces.is_empty() {
            return Err(InputError::new(format!(
                "radiosity: no surface of '{}' can receive light (no light, or every light is enclosed)",
                scene.name
            ))
            .into());
        }
        let triangle_sides = triangle_sides(gpu, &elements)?;
        let shaders = FullScreenShaders {
            vertex: shaders::RASTER_LIGHTING_VERT,
            fragment: shaders::GI_RADIOSITY_LIT_DISPLAY_FRAG,
        };
        let ambient = u32::from(settings.ambient);
        let lit_display = LitPipeline::new(gpu, scene, LIT_DISPLAY, shaders, |spec| {
            spec.with_u32(ids::RAD_AMBIENT_CONSTANT, ambient)
        })?;
        Ok(Radiosity {
            solver: Solver::new(gpu, scene, elements, settings.solver)?,
            triangle_ids: TriangleIds::new(gpu, "radiosity triangle ids")?,
            display: ComputePipeline::new(
                gpu,
                DISPLAY,
                shaders::GI_RADIOSITY_DISPLAY_COMP,
                &Specialization::new(),
            )?,
            lit_display,
            triangle_sides,
            simulated: SimulatedView::new(settings.decay_shots),
            simulated_changed: false,
            budgeted_shots: 1.0,
            last_frame: None,
            settings,
        })
    }

    /// What the display reads besides the G-buffer, for view `index`: the solution (surfaces,
    /// elements, their indirect irradiance, the shot's ambient term), the triangles' sides and
    /// the view's triangle ids.
    fn display_inputs(&self, index: usize) -> Vec<Binding<'_>> {
        let mut bindings = self.solver.display_bindings().to_vec();
        bindings.extend([
            Binding::texels(ids::RAD_TRIANGLE_SIDES, &self.triangle_sides),
            Binding::image_read(ids::RAD_TRIANGLE_IDS, self.triangle_ids.image(index)),
        ]);
        bindings
    }

    /// Shots this frame: as set, or adapted so the frame interval approaches the budget.
    fn shots_this_frame(&mut self) -> u32 {
        if let Some(shots) = self.settings.shots {
            return shots;
        }
        let now = Instant::now();
        if let Some(last) = self.last_frame.replace(now) {
            let ms = now.duration_since(last).as_secs_f64() * 1e3;
            let ratio = (self.settings.budget_ms / ms.max(1e-3)).clamp(0.5, 2.0);
            self.budgeted_shots = (self.budgeted_shots * ratio).clamp(1.0, 4096.0);
        }
        self.budgeted_shots.round() as u32
    }
}

impl GiMethod for Radiosity {
    fn name(&self) -> &'static str {
        "radiosity"
    }

    fn record_view(&mut self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        self.triangle_ids.fit_views(rec.gpu(), ctx.views)?;
        self.triangle_ids.record_view(rec, ctx, view)
    }

    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        let mode = self.settings.solver.mode;
        let restart = ctx.frame == 0 || ctx.changes.lights;
        let moved = restart || ctx.changes.camera || ctx.changes.views;
        // The first view's camera steers id and pd (a CAVE's other walls do not).
        let camera = ctx.views.first().map(|v| CameraView::of(&v.eye));
        if restart {
            self.solver.record_restart(rec, ctx.lights)?;
        }
        if let (true, true, Some(camera)) = (mode.follows_camera(), moved, camera) {
            self.solver.record_camera_importance(rec, &camera)?;
            self.simulated.reset(camera.vertical_fov_deg());
            self.simulated_changed = mode == Mode::Pd;
        }
        let state = self.solver.last_state();
        let settled = match mode {
            Mode::Pd => {
                !self.simulated_changed && self.simulated.saturated() && !state.may_deliver(self.simulated.generation)
            }
            _ => true,
        };
        if !moved && state.converged() && settled {
            return Ok(());
        }
        // Deliveries wait only after a view change until a pick finds none (the state may lag a
        // frame, which only records a few empty deliveries more).
        let mut deliver = state.may_deliver(self.simulated.generation);
        for _ in 0..self.shots_this_frame() {
            if let (Mode::Pd, Some(camera)) = (mode, camera) {
                let generation = self.simulated.generation;
                deliver |= self.simulated_changed;
                if self.simulated_changed && self.simulated.everything {
                    self.solver.record_visibility_everything(rec, generation)?;
                } else if self.simulated_changed {
                    let simulated = camera.widened(self.simulated.fov_deg);
                    self.solver.record_visibility(rec, &simulated, generation)?;
                }
                self.simulated_changed = false;
                if deliver {
                    self.solver.record_deliveries(rec, self.solver.slots())?;
                }
            }
            self.solver.record_shot(rec)?;
            if mode == Mode::Pd && self.simulated.count_shot() {
                self.simulated_changed = true;
            }
        }
        self.solver.record_state_copy(rec);
        Ok(())
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, index: usize) -> GpuResult<()> {
        let view = &ctx.views[index];
        let mut bindings = self.display_inputs(index);
        bindings.extend([
            Binding::image_read(ids::RAD_GBUFFER_POSITION, &view.gbuffer.position),
            Binding::image_read(ids::RAD_GBUFFER_ALBEDO, &view.gbuffer.albedo),
            Binding::image_write(ids::RAD_HDR, &view.hdr),
        ]);
        rec.compute(&ComputePass {
            name: DISPLAY,
            pipeline: &self.display,
            bindings: &bindings,
            push: &DisplayPush {
                eye: view.eye.position.extend(1.0).to_array(),
                size: [view.width(), view.height()],
                ambient: u32::from(self.settings.ambient),
            },
            threads: [view.width(), view.height(), 1],
        })
    }

    fn record_lit_lookup(
        &self,
        rec: &mut Recorder,
        _ctx: &FrameContext,
        index: usize,
        direct: &DirectDraw,
    ) -> GpuResult<bool> {
        let lit = self.lit_display.as_ref();
        lit.map_or(Ok(false), |lit| lit.draw(rec, direct, LIT_DISPLAY, self.display_inputs(index)))
    }

    fn pixel_passes(&self) -> Vec<PixelPass> {
        vec![
            PixelPass {
                pass: DISPLAY,
                bytes_per_pixel: DISPLAY_BYTES_PER_PIXEL,
                flops_per_pixel: DISPLAY_FLOPS_PER_PIXEL,
                with_direct_lighting: false,
                background_bytes: Some(DISPLAY_BACKGROUND_BYTES),
            },
            PixelPass {
                pass: LIT_DISPLAY,
                bytes_per_pixel: LIT_DISPLAY_BYTES_PER_PIXEL,
                flops_per_pixel: DISPLAY_FLOPS_PER_PIXEL,
                with_direct_lighting: true,
                background_bytes: Some(0.0),
            },
        ]
    }

    fn convergence(&self) -> Option<Convergence> {
        Some(Convergence {
            measure: "unshot power",
            remaining: self.solver.last_state().remaining(),
        })
    }

    fn describe(&self) -> Vec<String> {
        let e = &self.solver.elements;
        let o = self.solver.options();
        vec![
            format!(
                "radiosity: {} patches, {} surfaces, {} elements on the polygons ({} texels, side {:.4})",
                e.patches.len(),
                e.surfaces.len(),
                e.valid_count(),
                e.elements.len(),
                e.texel
            ),
            format!(
                "item buffer: {} {}² (mesh subdivided {}x), up to {} shooting locations per shot",
                if o.hemicube { "hemicube" } else { "stereographic" },
                o.resolution,
                o.item_level,
                self.solver.slots()
            ),
            format!(
                "mode {}: {}",
                self.settings.solver.mode.name(),
                self.status().unwrap_or_default()
            ),
        ]
    }

    fn status(&self) -> Option<String> {
        let state = self.solver.last_state();
        let mut line = format!(
            "{} shots, unshot power {:.2e} of the most ({})",
            state.shots(),
            state.remaining(),
            if state.converged() { "converged" } else { "refining" }
        );
        if self.settings.solver.mode == Mode::Pd {
            let view = if self.simulated.everything {
                "every surface".to_string()
            } else {
                format!("{:.0} deg", self.simulated.fov_deg)
            };
            line += &format!(
                ", simulated view {view}, {} table columns to deliver",
                state.table[0]
            );
        }
        Some(line)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn element_densities_parse_and_bad_ones_are_refused() {
        assert_eq!(parse_density("4096").unwrap(), Density::Budget(4096));
        assert_eq!(parse_density("2000/area").unwrap(), Density::PerArea(2000.0));
        for bad in ["0", "-5", "1.5", "nan", "inf/area", "0/area", "lots", "1e12"] {
            assert!(parse_density(bad).is_err(), "{bad}");
        }
    }
}
