//! ILPV in two scales (`--far-lattice`): 2-band SH with 26-neighbour transport turns diffusive
//! within a few cells (docs/lpv.md, "Why finer lattices lost"), so on a fine lattice light needs
//! many diffusive hops to cross a scene and the far walls starve while the near ones saturate.
//! Two lattices split the light by distance instead:
//!
//! * the near field, the user's fine lattice, holds this frame's injection and its first
//!   `near_steps` steps at λ_incr 0 (m < K): the short-range light, where a fine lattice resolves
//!   contact and blocking;
//! * the far field, a coarse lattice fitted to the scene, runs ILPV as configured (steps, λ_incr)
//!   from the same RSM and adds to the lookup everything after its own first step (m ≥ 1) and
//!   the share `far_injection` (α) of its injection, which covers the range between the near
//!   field's reach and one far cell: the long-range light, which crosses the scene in few hops
//!   before it diffuses.
//!
//! One lookup pass adds both fields into the HDR image (src/gi/lpv/lookup.rs). The far field leaks through geometry thinner than its
//! cells (it is coarse on purpose); the sealed-box leak tests run on one lattice.

use super::free_path::mean_free_path;
use super::lookup::{Lookup, lookup_passes};
use super::technique::{FarLattice, Field, IlpvLookup, Lpv, LpvSettings, Scheme};
use crate::gi::registry::Setup;
use crate::gi::{Convergence, CorePass, Follow, FrameContext, GiMethod, PixelPass};
use crate::gpu::{Gpu, GpuError, GpuResult, Recorder};
use crate::render::passes::DirectDraw;
use crate::scene::Scene;
use crate::scene::dynamic::Aabb;

/// `--far-lattice auto`: far cells of this many mean free paths of the scene (0.45: 5 cells
/// across the Cornell box, about 11 across four-boxes, where the grids in docs/lpv.md found
/// 5 and 12 best).
pub const FAR_CELL_IN_FREE_PATHS: f64 = 0.45;

pub struct TwoScale {
    pub near: Lpv,
    pub far: Lpv,
    /// Both fields' lookup, in one pass.
    lookup: Lookup,
}

impl TwoScale {
    /// The two lattices of ILPV `settings`, whose far lattice has `far_cells` cells.
    pub fn new(setup: &Setup, settings: LpvSettings, far_cells: u32) -> anyhow::Result<TwoScale> {
        let near = LpvSettings {
            incremental: 0.0,
            iterations: settings.near_steps,
            far_lattice: FarLattice::Off,
            ..settings.clone()
        };
        near.validate()?;
        let near = Lpv::with_field(setup, near, Field::Whole)?;
        // Both fields record the same parts: the far field carries the channels as the near
        // field's plan does.
        let far = LpvSettings {
            lattice: far_cells,
            far_lattice: FarLattice::Off,
            channels: Some(near.plan),
            ..settings
        };
        let far = Lpv::with_field(setup, far, Field::Far)?;
        let lookup = Lookup::new(
            setup.gpu,
            setup.scene,
            &[near.lookup_field(), far.lookup_field()],
            near.settings.lookup_resolution,
            near.lookup_filter,
        )?;
        Ok(TwoScale { near, far, lookup })
    }
}

impl GiMethod for TwoScale {
    fn name(&self) -> &'static str {
        self.near.name()
    }

    fn state_digest(&self, gpu: &Gpu) -> GpuResult<Option<u64>> {
        let near = self.near.digest(gpu, crate::digest::FNV_OFFSET)?;
        self.far.digest(gpu, near).map(Some)
    }

    fn record_view(&mut self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        self.lookup.fit_view(rec.gpu(), ctx.views, view)
    }

    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        self.near.record_light(rec, ctx)?;
        let rsm = self
            .near
            .rsm()
            .ok_or_else(|| GpuError::Setup("the near field renders no RSM".into()))?;
        self.far.record_light_from(rec, ctx, rsm)?;
        // The far field injects from the near field's RSM, which is rendered only when the
        // near field does not reuse its injection: both decide from the same changes.
        if self.near.reuses_injection() != self.far.reuses_injection() {
            return Err(GpuError::Setup(
                "the near and far fields disagree on reusing their injection".into(),
            ));
        }
        Ok(())
    }

    fn parts(&self) -> &'static [&'static str] {
        self.near.parts()
    }

    fn record_part(&mut self, rec: &mut Recorder, ctx: &FrameContext, part: usize) -> GpuResult<()> {
        self.near.record_part(rec, ctx, part)?;
        self.far.record_part(rec, ctx, part)
    }

    fn light_done(&mut self, ctx: &FrameContext) {
        self.near.light_done(ctx);
        self.far.light_done(ctx);
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        let fields = [self.near.lookup_field(), self.far.lookup_field()];
        self.lookup.record(rec, ctx, view, &fields)
    }

    fn record_lit_lookup(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        direct: &DirectDraw,
    ) -> GpuResult<bool> {
        let fields = [self.near.lookup_field(), self.far.lookup_field()];
        self.lookup.record_lit(rec, (ctx, view), direct, &fields)
    }

    fn geometry_moved(
        &mut self,
        _gpu: &Gpu,
        scene: &Scene,
        regions: &[Aabb],
    ) -> anyhow::Result<Follow> {
        self.near.follow_geometry(scene, regions);
        self.far.follow_geometry(scene, regions);
        Ok(Follow::Followed)
    }

    fn status(&self) -> Option<String> {
        let (near, far) = (self.near.geometry_update()?, self.far.geometry_update()?);
        Some(format!(
            "geometry lattices: {} of {} near and {} of {} far cells rebuilt in {:.1} ms at the last move",
            near.rebuilt,
            near.cells,
            far.rebuilt,
            far.cells,
            near.milliseconds + far.milliseconds
        ))
    }

    /// The near field is complete every frame; the far field carries the blend.
    fn convergence(&self) -> Option<Convergence> {
        self.far.convergence()
    }

    /// The near field's propagation (the far field's is the pass `far propagate`: its few
    /// cells would hide the lattice the user sized).
    fn core_pass(&self) -> Option<CorePass> {
        self.near.core_pass()
    }

    /// Both lattices' lookup, in one pass.
    fn pixel_passes(&self) -> Vec<PixelPass> {
        lookup_passes(2, self.near.settings.lookup_resolution)
    }

    fn describe(&self) -> Vec<String> {
        let field = |label: &str, lines: Vec<String>| -> Vec<String> {
            lines.into_iter().map(|l| format!("{label}: {l}")).collect()
        };
        let mut lines = field("near field", self.near.describe());
        lines.extend(field("far field (its steps, and --far-injection of its injection)", self.far.describe()));
        lines.push(self.lookup.describe());
        lines
    }
}

/// The method `settings` asks for: two scales when `far_lattice` is set, else one lattice.
pub fn create(setup: &Setup, settings: LpvSettings) -> anyhow::Result<Box<dyn GiMethod>> {
    let far_cells = match (settings.scheme, settings.far_lattice) {
        (Scheme::Lpv, _) | (_, FarLattice::Off) => None,
        (Scheme::Ilpv, FarLattice::Cells(n)) => Some(n),
        // The thesis's final lookup cannot leave out the near field's steps: one lattice.
        (Scheme::Ilpv, FarLattice::Auto) if settings.ilpv_lookup == IlpvLookup::Final => None,
        (Scheme::Ilpv, FarLattice::Auto) => auto_far_cells(setup, &settings),
    };
    match far_cells {
        Some(cells) => {
            settings.validate()?;
            settings.validate_two_scale()?;
            Ok(Box::new(TwoScale::new(setup, settings, cells)?))
        }
        None => Ok(Box::new(Lpv::new(setup, settings)?)),
    }
}

/// Far cells along the longest axis for `--far-lattice auto`: cells of
/// [`FAR_CELL_IN_FREE_PATHS`] mean free paths (at least 2). None, one lattice, where no ray
/// between surfaces gives a free path (a lone plane), and where the near lattice is less than
/// twice as fine: two lattices of about the same cells count the short range twice (on
/// four-boxes at 10 cells the two-scale relMSE was 8x the one lattice's).
fn auto_far_cells(setup: &Setup, settings: &LpvSettings) -> Option<u32> {
    let scene = setup.scene;
    (setup.progress)("mean free path", 0.0);
    let Some(path) = mean_free_path(&scene.mesh) else {
        log::info!("--far-lattice auto: no free path between the scene's surfaces; one lattice");
        return None;
    };
    let longest = f64::from((scene.bounds_max - scene.bounds_min).max_element());
    let cells = ((longest / (FAR_CELL_IN_FREE_PATHS * path)).round() as u32).max(2);
    let fits = 2 * cells <= settings.lattice;
    log::info!(
        "--far-lattice auto: mean free path {path:.4}, far lattice {cells} cells{}",
        if fits {
            String::new()
        } else {
            format!(" (not under half of --lattice {}: one lattice)", settings.lattice)
        }
    );
    fits.then_some(cells)
}
