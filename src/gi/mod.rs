//! Global-illumination methods as plug-ins: the trait every method implements, the frame
//! context it gets, and the registration of every method (one line each, at the bottom).
//!
//! A frame (src/render/frame.rs) calls a method at fixed points, in this order:
//! 1. [`GiMethod::record_view`] once per view, after every view's G-buffer (e.g. placing cache
//!    records where a view needs them);
//! 2. [`GiMethod::record_light`] once per frame for all views (e.g. RSM, injection);
//! 3. [`GiMethod::record_part`] for each of its independent [`GiMethod::parts`], each of which
//!    may run on its own async compute queue;
//! 4. [`GiMethod::light_done`] on the CPU, once every part is recorded;
//! 5. [`GiMethod::record_lookup`] once per view, after the view's direct light, to add indirect
//!    light to the view's HDR image; or, where the method can, [`GiMethod::record_lit_lookup`]
//!    to draw the view's direct light and its indirect light in one pass.
//!
//! Between frames, whoever drives them (the runner, the viewer) hands a method the geometry that
//! moved ([`GiMethod::geometry_moved`]) and builds the method again where it cannot follow.
//!
//! Methods see the frame only through [`FrameContext`] (scene buffers, shadow maps, views) and,
//! to draw direct lighting with their own light, through the frame's passes' [`DirectDraw`], so
//! this module sits below the frame and never imports it.

pub mod registry;
pub mod settings;
pub mod shared;

use serde::Serialize;

use crate::gpu::{Gpu, GpuResult, Image, Recorder, Sampler};
use crate::render::passes::DirectDraw;
use crate::render::targets::View;
use crate::scene::dynamic::Aabb;
use crate::scene::gpu::SceneBuffers;
use crate::scene::{Light, Scene};

/// What changed since the method's previous frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Changes {
    /// Lights moved, were aimed, recoloured or dimmed.
    pub lights: bool,
    /// A view's eye moved.
    pub camera: bool,
    /// Views were created anew (a resize, another CAVE): per-view state must be rebuilt.
    pub views: bool,
    /// Geometry moved (a dynamic object or an emitter): the vertex buffer holds it this frame.
    pub geometry: bool,
}

impl Changes {
    /// Everything changed (a method's first frame).
    pub const ALL: Changes = Changes {
        lights: true,
        camera: true,
        views: true,
        geometry: true,
    };

    pub fn any(&self) -> bool {
        self.lights || self.camera || self.views || self.geometry
    }
}

/// How a method took moved geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Follow {
    /// It updated what it keeps of the geometry.
    Followed,
    /// It cannot follow: build it again for the moved scene.
    Rebuild,
}

/// What a method may read of the frame it records into.
pub struct FrameContext<'a> {
    pub scene: &'a SceneBuffers,
    /// Depth of every shadow view, one layer each (see `SceneBuffers::shadow_views`).
    pub shadow_map: &'a Image,
    pub shadow_sampler: &'a Sampler,
    pub views: &'a [View],
    /// The lights as they are this frame (as in `scene.lights`, on the CPU).
    pub lights: &'a [Light],
    /// The lights the rasteriser draws, in the order of `scene.lights` on the GPU: `lights`,
    /// then the area-light samples (see `Scene::raster_lights`).
    pub raster_lights: &'a [Light],
    /// Frames the method was given before this one (0: its first frame, see
    /// `Frame::restart_method`).
    pub frame: u64,
    /// What changed since the previous frame (everything, on the first frame).
    pub changes: Changes,
    /// The lights move in every frame (`FrameOptions::lights_move`): what depends on them alone
    /// is redone every frame, so keeping it for a later frame is wasted work.
    pub lights_move: bool,
    /// The HDR images carry indirect light alone (no direct light, no emission).
    pub indirect_only: bool,
}

/// How far a progressive or incremental method has come.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Convergence {
    /// What `remaining` measures, e.g. "unshot power" or "blend weight of old light".
    pub measure: &'static str,
    /// The fraction still to go: 1 just after a change, 0 converged.
    pub remaining: f64,
}

/// A method's core pass, the one `vkgi profile` measures per unit of work against the device's
/// bandwidth and arithmetic bounds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CorePass {
    /// The pass's name in the profile (its `ScopeTag::pass`).
    pub pass: &'static str,
    /// What one unit of work is (e.g. "cell").
    pub unit: &'static str,
    /// Units one run of the pass processes.
    pub units: usize,
    /// What a run must move and compute per unit, for the roofline bound.
    pub cost: UnitCost,
    /// Where a frame's first run of the pass must do less (a propagation's first step, which
    /// blocks nothing), what it must do: the profile holds that run to it and leaves it out of
    /// the pass's median.
    pub first_run: Option<UnitCost>,
}

/// Bytes moved and flops done per unit of a pass's work at the ideal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct UnitCost {
    pub bytes: f64,
    pub flops: f64,
}

/// A pass that runs once per pixel of a view, and what it must move and compute per pixel at
/// the ideal, for the bound `vkgi profile` measures it against.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PixelPass {
    /// The pass's name in the profile (its `ScopeTag::pass`).
    pub pass: &'static str,
    pub bytes_per_pixel: f64,
    pub flops_per_pixel: f64,
    /// The pass draws the frame's direct lighting too ([`GiMethod::record_lit_lookup`]): its
    /// bound is direct lighting's plus these bytes and flops.
    pub with_direct_lighting: bool,
    /// Where a pixel that no surface covers needs less: the bytes it must move there (whether
    /// a surface covers it read from the depth, 4 B, and what the pass must write there), and
    /// no arithmetic. None: every pixel costs the same.
    pub background_bytes: Option<f64>,
}

impl PixelPass {
    /// The bytes and flops the pass must move and compute at the ideal over `pixels` pixels, of
    /// which `covered` show a surface.
    pub fn ideal(&self, pixels: usize, covered: usize) -> (f64, f64) {
        let (pixels, covered) = (pixels as f64, covered.min(pixels) as f64);
        match self.background_bytes {
            None => (self.bytes_per_pixel * pixels, self.flops_per_pixel * pixels),
            Some(background) => (
                self.bytes_per_pixel * covered + background * (pixels - covered),
                self.flops_per_pixel * covered,
            ),
        }
    }
}

/// A GI method: persistent GPU state plus the passes it adds to a frame.
pub trait GiMethod {
    /// The name it is registered under (tags its passes in the profile).
    fn name(&self) -> &'static str;

    /// Work for view `view` (an index into `ctx.views`) after every view's G-buffer and before
    /// the light work.
    fn record_view(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
    ) -> GpuResult<()> {
        let _ = (rec, ctx, view);
        Ok(())
    }

    /// Work once per frame for all views, on the graphics queue.
    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()>;

    /// Labels of the independent parts recorded by [`GiMethod::record_part`] (none by
    /// default). Parts may run concurrently, each on its own compute queue, after the light
    /// work and before any lookup; no part may touch a resource another part writes (the
    /// frame fails with an error naming it, `render::part_ledger`).
    fn parts(&self) -> &'static [&'static str] {
        &[]
    }

    /// Part `part` of this frame's light work.
    fn record_part(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        part: usize,
    ) -> GpuResult<()> {
        let _ = (rec, ctx, part);
        Ok(())
    }

    /// Every part of this frame is recorded: from now on lookups read this frame's light.
    fn light_done(&mut self, ctx: &FrameContext) {
        let _ = ctx;
    }

    /// Add indirect radiance to view `view`'s HDR image (after its direct lighting).
    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()>;

    /// Draw view `view`'s direct lighting (`direct`) with this method's indirect radiance
    /// added, in one pass, instead of [`GiMethod::record_lookup`] after the frame's direct
    /// lighting: the G-buffer is read once and the HDR image written once. False, with nothing
    /// recorded, where the method has no such pass (the default) or none for `direct`'s shape:
    /// the frame then records the two apart.
    fn record_lit_lookup(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        direct: &DirectDraw,
    ) -> GpuResult<bool> {
        let _ = (rec, ctx, view, direct);
        Ok(false)
    }

    /// Geometry moved before the next frame: `scene` is the scene as it is now and `regions` the
    /// world boxes whose geometry changed (where each moved object was and where it is). The
    /// frame's vertex buffer holds the new geometry from the next frame on. A method that keeps
    /// state built from the geometry on the CPU updates it (only where `regions` touch, if it
    /// can) and returns [`Follow::Followed`]; by default it asks to be built again.
    fn geometry_moved(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        regions: &[Aabb],
    ) -> anyhow::Result<Follow> {
        let _ = (gpu, scene, regions);
        Ok(Follow::Rebuild)
    }

    /// Progress of a method that refines across frames (None: each frame is complete).
    fn convergence(&self) -> Option<Convergence> {
        None
    }

    /// The pass `vkgi profile` measures against the device's bounds, if the method has one.
    fn core_pass(&self) -> Option<CorePass> {
        None
    }

    /// The method's per-pixel passes (e.g. its lookup), which `vkgi profile` measures per pixel
    /// against the device's bounds.
    fn pixel_passes(&self) -> Vec<PixelPass> {
        Vec::new()
    }

    /// Lines for the profile: how the method runs (lattice, kernels, cache sizes...).
    fn describe(&self) -> Vec<String>;

    /// One line of live state for the viewer's overlay (e.g. shots done, power left).
    fn status(&self) -> Option<String> {
        None
    }

    /// A digest of the light state the method carries into the next frame and looks up (the
    /// nodes of a CAVE compare theirs frame by frame; None: the method carries none). Reads
    /// GPU buffers back: call it between frames, after the last one finished.
    fn state_digest(&self, _gpu: &Gpu) -> GpuResult<Option<u64>> {
        Ok(None)
    }
}

/// Declares each method's module and registers its entries: one line per method.
macro_rules! methods {
    ($($method:ident,)*) => {
        $(pub mod $method;)*
        /// Every registered method's entries, in registration order.
        pub(crate) const REGISTERED: &[&[registry::MethodEntry]] = &[$($method::METHODS),*];
    };
}

methods! {
    ambient,
    lpv,
    lightwave,
    radiosity,
    irradiance_cache,
    radiance_volumes,
}
