//! `irradiance-cache`, seed 003 (Křivánek & Gautron, "Practical Global Illumination with
//! Irradiance Caching", ch. 8; spec 003): irradiance records placed where the view lacks them,
//! each record's hemisphere rasterised from the record and reduced on the GPU to its irradiance,
//! rotation and translation gradients and harmonic mean distance, and every record splatted onto
//! the view as a screen-space quad weighted by Ward's function with gradient extrapolation.
//!
//! Each view, every frame: splat all records; then rounds of placement, each finding uncovered
//! pixels (accumulated weight below a), adding records there, rendering and reducing their
//! hemispheres and splatting them. Placement is `tiles` (spec §17 mode B: the least covered
//! pixel of each tile, 32 → 16 → 8 pixels, a budget per frame) or `scan` (mode A, the chapter's
//! order: the first uncovered pixel in scan order, one record per round). Records persist while
//! the camera moves and are dropped when lights or geometry change. With `--bounces` past 1,
//! once placement settles the frame's light work recomputes every record from hemispheres lit
//! by a snapshot of the previous bounce's cache (passes.rs, `record_refresh`).

pub mod bindings;
pub mod coverage_study;
pub mod cpu;
pub mod passes;
pub mod records;
pub mod tables;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};
use crate::gi::{Convergence, FrameContext, GiMethod, PixelPass};
use crate::gpu::{GpuResult, Recorder};
use crate::reference::Bounces;
use passes::Passes;
use records::CacheState;
use tables::Coverage;

const SETTINGS: &[Setting] = &[
    Setting::new(
        "accuracy",
        Kind::Float { min: 0.02, max: 4.0 },
        "0.5",
        "Ward's a: a record reaches a·R (R its harmonic mean distance); smaller places more records (the chapter: 0.1-0.15 offline, 0.5 interactive)",
    )
    .keys('9', '0', 1.25),
    Setting::new(
        "hemisphere",
        Kind::Choice(Coverage::NAMES),
        "stretch",
        "Directions the record's 126.87° plane misses: stretch border texels to the horizon (the chapter), leave them black (plane), or divide by the plane's coverage ([LC04])",
    ),
    Setting::new(
        "hemisphere-size",
        Kind::Int { min: 8, max: 256 },
        "64",
        "Side of a record's hemisphere image in texels",
    ),
    Setting::new(
        "placement",
        Kind::Choice(&["tiles", "scan"]),
        "tiles",
        "tiles: the least covered pixel of every 32, 16 and 8 pixel tile in three rounds a frame (GPU-only, spec §17 B); scan: the first uncovered pixel in scan order, one record a round (the chapter's order, §17 A)",
    ),
    Setting::new(
        "records",
        Kind::Int { min: 1, max: 1 << 20 },
        "16384",
        "Records the cache holds; a full cache places no more (counted in the profile)",
    ),
    Setting::new(
        "records-per-frame",
        Kind::Int { min: 1, max: 1024 },
        "96",
        "New records a frame may place, per view (the chapter's interactive mode: 100)",
    ),
    Setting::new(
        "ic-weight",
        Kind::Choice(&["smooth", "ward"]),
        "smooth",
        "smooth: w - 1/a, fading to 0 at the zone's edge (§8.2); ward: w as Eq. 8.2",
    ),
    Setting::new(
        "normal-factor",
        Kind::Float { min: 0.0, max: 10.0 },
        "1",
        "κ in the weight's normal term √(κ(1 - n·n_k)): 1 as Eq. 8.2, 0.2 as the chapter's Alg. 3",
    ),
    Setting::new(
        "bounces",
        Kind::Text,
        "1",
        "Bounces of indirect light, 1-32 or inf: past the first, once placement settles, every record is recomputed from hemispheres lit by the previous bounce's cache (inf: until Σ E changes by under 0.1%)",
    ),
];

/// Records `render` and `report` give the placement room for by default (the Cornell box at
/// 256×192 needs 602 at a = 0.5 and 2 574 at a = 0.15); placement stops by itself once no hole
/// is left.
const SETTLE_RECORDS: u32 = 2304;

pub const METHODS: &[MethodEntry] = &[MethodEntry {
    name: "irradiance-cache",
    description: "seed 003: irradiance caching on the GPU, records placed where the view needs them, hemispheres rasterised and reduced on the GPU, splatted with Ward's weights and gradients",
    default: false,
    settings: SETTINGS,
    settle_frames: |settings| {
        let per_frame = settings.u32("records-per-frame").unwrap_or(1).max(1);
        let bounces = match settings.text("bounces").map(parse_bounces) {
            Ok(Ok(Bounces::Limited(n))) => n,
            _ => SETTLE_BOUNCES,
        };
        SETTLE_RECORDS.div_ceil(per_frame) * bounces
    },
    profile_axis: None,
    create: |setup, settings| Ok(Box::new(IrradianceCache::new(setup, settings)?)),
}];

/// Bounces `render` and `report` give `--bounces inf` room for by default (the Cornell box's
/// Σ E settles to 0.1% after 9).
const SETTLE_BOUNCES: u32 = 12;

/// `--bounces`: 1 to IC_MAX_BOUNCES, or inf.
fn parse_bounces(text: &str) -> Result<Bounces, InputError> {
    match Bounces::parse(text) {
        Ok(Bounces::Limited(n)) if (1..=bindings::IC_MAX_BOUNCES).contains(&n) => {
            Ok(Bounces::Limited(n))
        }
        Ok(Bounces::Unlimited) => Ok(Bounces::Unlimited),
        _ => Err(InputError::new(format!(
            "--bounces {text}: the cache holds 1 to {} bounces, or inf",
            bindings::IC_MAX_BOUNCES
        ))),
    }
}

/// How records are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// Spec §17 mode B: rounds of tile-wise candidates.
    Tiles,
    /// Spec §17 mode A: the first uncovered pixel in scan order, one per round.
    Scan,
}

/// The method's settings, parsed and checked.
#[derive(Clone, Debug)]
pub struct CacheSettings {
    pub weighting: cpu::Weighting,
    pub coverage: Coverage,
    pub hemisphere_size: u32,
    pub placement: Placement,
    pub capacity: u32,
    pub per_frame: u32,
    pub bounces: Bounces,
}

impl CacheSettings {
    pub fn parse(settings: &Settings) -> Result<Self, InputError> {
        let hemisphere = settings.text("hemisphere")?;
        Ok(CacheSettings {
            weighting: cpu::Weighting {
                accuracy: settings.float("accuracy")?,
                smooth: settings.text("ic-weight")? == "smooth",
                normal_factor: settings.float("normal-factor")?,
                max_weight: f64::from(bindings::IC_MAX_WEIGHT),
            },
            coverage: Coverage::parse(hemisphere).ok_or_else(|| {
                InputError::new(format!(
                    "--hemisphere {hemisphere}: not one of {}",
                    Coverage::NAMES.join(", ")
                ))
            })?,
            hemisphere_size: settings.u32("hemisphere-size")?,
            placement: match settings.text("placement")? {
                "scan" => Placement::Scan,
                _ => Placement::Tiles,
            },
            capacity: settings.u32("records")?,
            per_frame: settings.u32("records-per-frame")?,
            bounces: parse_bounces(settings.text("bounces")?)?,
        })
    }
}

pub struct IrradianceCache {
    pub settings: CacheSettings,
    pub passes: Passes,
}

impl IrradianceCache {
    pub fn new(setup: &Setup, settings: &Settings) -> anyhow::Result<IrradianceCache> {
        IrradianceCache::with(setup, CacheSettings::parse(settings)?)
    }

    pub fn with(setup: &Setup, settings: CacheSettings) -> anyhow::Result<IrradianceCache> {
        let passes = Passes::new(setup.gpu, setup.scene, &settings)?;
        Ok(IrradianceCache { settings, passes })
    }

    /// The cache's counters as the most recent finished frame left them.
    pub fn state(&self) -> CacheState {
        self.passes.last_state()
    }

    /// Whether `state` (of a finished frame) holds every bounce asked for in the cache the
    /// passes keep: the refresh has nothing to do until the cache is emptied.
    fn bounces_done(&self, state: &CacheState) -> bool {
        state.generation == self.passes.generation() && state.done == 1
    }

    /// The fraction of the bounce refresh still to go: 0 for one bounce or when done.
    fn bounces_left(&self, state: &CacheState) -> f64 {
        if self.settings.bounces == Bounces::Limited(1) || self.bounces_done(state) {
            return 0.0;
        }
        let refresh = if state.previous_count > 0 {
            f64::from(state.previous_count - state.refreshed.min(state.previous_count))
                / f64::from(state.previous_count)
        } else {
            0.0
        };
        match self.settings.bounces {
            Bounces::Limited(n) => {
                (f64::from(n - state.bounce.min(n)) + refresh) / f64::from(n.max(2) - 1)
            }
            Bounces::Unlimited if state.bounce <= 1 => 1.0,
            Bounces::Unlimited => refresh.max(f64::from(state.change)).min(1.0),
        }
    }
}

impl GiMethod for IrradianceCache {
    fn name(&self) -> &'static str {
        "irradiance-cache"
    }

    fn record_view(&mut self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        let changes = ctx.changes;
        if view == 0 && ctx.frame > 0 && (changes.lights || changes.geometry) {
            self.passes.empty();
        }
        self.passes.record_view(rec, ctx, view, &self.settings)
    }

    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        if self.settings.bounces != Bounces::Limited(1) && !self.bounces_done(&self.state()) {
            self.passes.record_refresh(rec, ctx, &self.settings)?;
        }
        self.passes.record_state_copy(rec);
        Ok(())
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        self.passes.record_normalise(rec, &ctx.views[view], view)
    }

    fn convergence(&self) -> Option<Convergence> {
        let state = self.state();
        let placement = f64::from(state.holes) / f64::from(state.holes + state.count).max(1.0);
        Some(Convergence {
            measure: "tiles with an uncovered pixel in the last round against them and the records held, or the bounces left to compute if more",
            remaining: placement.max(self.bounces_left(&state)),
        })
    }

    fn pixel_passes(&self) -> Vec<PixelPass> {
        vec![passes::normalise_pass()]
    }

    fn describe(&self) -> Vec<String> {
        let s = &self.settings;
        let state = self.state();
        vec![
            format!(
                "irradiance cache: a = {}, {} weights, κ = {}, hemisphere {}² ({:?}), {:?} placement, {} records a frame, {} at most, bounces {:?}",
                s.weighting.accuracy,
                if s.weighting.smooth { "smooth" } else { "Ward" },
                s.weighting.normal_factor,
                s.hemisphere_size,
                s.coverage,
                s.placement,
                s.per_frame,
                s.capacity,
                s.bounces
            ),
            format!(
                "irradiance cache: {} records, {} uncovered tiles in the last round, {} refused (cache full), bounce {} ({} of {} refreshed, Σ E changed {:.2e})",
                state.count,
                state.holes,
                state.overflowed,
                state.bounce,
                state.refreshed,
                state.previous_count,
                state.change
            ),
        ]
    }

    fn status(&self) -> Option<String> {
        let state = self.state();
        let bounce = if self.settings.bounces == Bounces::Limited(1) {
            String::new()
        } else {
            format!(
                ", bounce {} ({}/{} refreshed)",
                state.bounce, state.refreshed, state.previous_count
            )
        };
        Some(format!(
            "records {} (+{} last round), holes {}{bounce}{}",
            state.count,
            state.added,
            state.holes,
            if state.overflowed > 0 {
                format!(", {} refused: cache full", state.overflowed)
            } else {
                String::new()
            }
        ))
    }
}
