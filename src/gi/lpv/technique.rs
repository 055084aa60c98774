//! The LPV method on the GPU: its settings, its persistent resources, and the passes it adds
//! to a frame: reflective shadow maps, VPL injection, (ILPV) the blend with last frame's light,
//! propagation per colour channel (the method's three independent parts), and the lookup into
//! the HDR image.

use ash::vk;
use glam::DVec4;

use super::autotune;
use super::bindings as ids;
use super::cost::{self, StepWork, StepWrites};
use super::geometry::{self, BlockingLobe, GeometryLattice};
use super::lattice::{CellBox, CellOrder, Lattice};
use super::lookup::{
    LOOKUP_BORDER, LatticeReads, Lookup, LookupField, LookupFilter, LookupResolution, lookup_passes,
};
use super::transfer::{FaceScheme, TransferVectors};
use crate::error::InputError;
use crate::gi::registry::Setup;
use crate::gi::shared::rsm::Rsm;
use crate::gi::shared::sh;
use crate::gi::{Convergence, CorePass, Follow, FrameContext, GiMethod, PixelPass, UnitCost};
use crate::scene::dynamic::Aabb;
use crate::scene::{Light, Scene};
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuError, GpuResult, Image,
    ImageDesc, Part, Recorder, Specialization,
};
use crate::render::part_ledger::PartLedger;
use crate::render::passes::DirectDraw;
use crate::shaders;

/// Which propagation scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Scheme {
    /// Classic 6-neighbour, 5-face LPV with an accumulation lattice (Kaplanyan & Dachsbacher).
    Lpv,
    /// Seed 000's incremental 26-neighbour LPV.
    Ilpv,
}

/// How σa and σs become per-step probabilities λ on the lattice (d̄ = mean neighbour distance).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Extinction {
    /// The thesis: λ = σ^d̄ (σ in [0, 1]; depends on the world unit: with d̄ a few centimetres
    /// σ^d̄ is near 1 for any σ, with d̄ in millimetres near 1 sooner still).
    Thesis,
    /// Beer–Lambert: λ = 1 - exp(-σ d̄), σ per metre (scene units are metres once a scene file's
    /// `scale` applies) and d̄ the mean step in metres.
    Physical,
}

/// What the ILPV lookup reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum IlpvLookup {
    /// The sum of this frame's merged lattice and its steps before the last, divided by the
    /// blend's weight of new light (1 - λ_incr): in the steady state Σ_m λ^m times the light
    /// each window of N steps carries, i.e. accumulated propagation reaching N/(1-λ) steps.
    /// Times d̄ = 1.416: a 26-neighbour step moves light d̄ cells on average, so a cell holds
    /// light for 1/d̄ of the steps a packet at one cell per step would spend in it.
    Accumulated,
    /// The thesis: the last step's lattice alone, scaled by its mean effective depth N/(1-λ)
    /// to turn a snapshot of travelling flux into radiance (spec 000 §6.2).
    Final,
}

/// Default cells along the scene's longest axis. Chosen by the accuracy grid on the Cornell box
/// (docs/lpv.md): 2-band SH spreads light sideways near surfaces, which finer lattices resolve
/// into visible error; 10 cells beat the best constant ambient term on every metric there.
pub const DEFAULT_LATTICE: u32 = 10;
/// Default propagation steps per frame (the thesis's 8).
pub const DEFAULT_ITERATIONS: u32 = 8;
/// Default λ_incr (the thesis found 0.5 best).
pub const DEFAULT_INCREMENTAL: f32 = 0.5;
/// Default lookup offset along the normal, in cells: 1, where the thesis has 0.5. Decided by
/// the accuracy grid: it reads light in front of the surface rather than the surface's own
/// outgoing VPL light (RMSE 0.047 instead of 0.061 at 8 cells on the Cornell box).
pub const DEFAULT_LOOKUP_OFFSET: f32 = 1.0;
/// Default VPL injection offset along the normal, in cells (the thesis's 0.5).
pub const DEFAULT_INJECT_OFFSET: f32 = 0.5;
/// Default RSM resolution (the thesis's 256²).
pub const DEFAULT_RSM: u32 = 256;
/// Default near-field steps of two-scale ILPV (the two-scale grid in docs/lpv.md).
pub const DEFAULT_NEAR_STEPS: u32 = 2;
/// Default share of its own injection two-scale ILPV's far field keeps (the two-scale grid in
/// docs/lpv.md).
pub const DEFAULT_FAR_INJECTION: f32 = 0.3;

/// Which part of the light transport one lattice models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// All of it: one lattice, or the fine lattice of two scales (the near field: this frame's
    /// injection and its first steps at λ_incr 0).
    Whole,
    /// Two scales, the coarse lattice: everything after its first step, and a share of its
    /// injection (it shares the near field's RSM; the near field resolves the short range).
    Far,
}

/// Mean distance to the 26 neighbours in cells: (6 + 12√2 + 8√3) / 26.
pub const MEAN_NEIGHBOUR_DISTANCE: f64 = 1.416_421_8;
/// Samples per neighbour cell for the transfer vectors (fixed seed).
const TRANSFER_SAMPLES: usize = 20_000;
const TRANSFER_SEED: u64 = 0x000c_0ffe_e000;

#[derive(Clone, Debug, serde::Serialize)]
pub struct LpvSettings {
    pub scheme: Scheme,
    /// Cells along the scene's longest axis.
    pub lattice: u32,
    /// Propagation steps per frame.
    pub iterations: u32,
    /// λ_incr, the weight of last frame's light (ILPV only; 0 = plain propagation).
    pub incremental: f32,
    /// RSM resolution per light view.
    pub rsm: u32,
    pub absorption: f32,
    pub scattering: f32,
    pub extinction: Extinction,
    pub blocking_lobe: BlockingLobe,
    /// Scale of the geometry lattice: 1 = a surface filling a cell's cross-section blocks a
    /// face-neighbour transfer completely (the thesis leaves the weights open).
    pub blocking_strength: f32,
    /// Apply no blocking in the first step of a frame (the thesis).
    pub first_step_unblocked: bool,
    /// The propagation kernel; None: the faster on this device, measured once
    /// (`--kernel auto`, autotune.rs).
    pub kernel: Option<Kernel>,
    /// How a step's dispatches carry the colour channels; None: the faster on this device,
    /// measured with the kernel (`--channel-plan auto`, autotune.rs).
    pub channels: Option<ChannelPlan>,
    /// How the lattices' buffers hold their cells; None: [`CellOrder::for_step`] of the
    /// lattice's kernel (`--cell-order auto`).
    pub cell_order: Option<CellOrder>,
    /// Rescale cells so each 26-neighbour step conserves energy despite the clamp.
    pub clamp_compensation: bool,
    pub ilpv_lookup: IlpvLookup,
    /// VPLs move this many cells before injection (the thesis: 0.5, along the normal).
    pub inject_offset: f32,
    /// Which way VPLs move before injection.
    pub inject_toward: InjectToward,
    /// How VPLs add into their cells.
    pub injection: Injection,
    /// The lookup reads this many cells along the surface normal (the thesis: 0.5).
    pub lookup_offset: f32,
    /// Where the lookup evaluates the lattices: every pixel, or every fourth with an upsample.
    pub lookup_resolution: LookupResolution,
    /// How the lookup reads the lattices (None: [`LookupFilter::for_device`]).
    pub lookup_filter: Option<LookupFilter>,
    /// ILPV in two scales: the coarse far-field lattice (see [`super::two_scale`]).
    pub far_lattice: FarLattice,
    /// Two scales: steps per frame of the fine near-field lattice (at λ_incr 0).
    pub near_steps: u32,
    /// Two scales: the share of its own injection the far field's lookup keeps (the rest is
    /// the near field's).
    pub far_injection: f32,
}

/// Which way a VPL moves before injection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum InjectToward {
    /// Along its normal (the thesis).
    Normal,
    /// Toward the light it reflects, at most half way: that segment is free of geometry (the
    /// light reached the VPL along it), so the VPL lands on its lit side even at the edge of a
    /// box around the light, where moving along one face's normal leaves it in a cell centred
    /// outside the next face.
    Light,
}

/// How a propagation step reads its source cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Kernel {
    /// A workgroup loads its cells and a one-cell halo into shared memory (z padded) and each
    /// thread gathers from there: the thesis's CUDA kernel, for GPUs.
    Tiled,
    /// Each thread gathers from global memory (for comparison).
    Naive,
    /// Each thread steps along z through a bundle of 2x2 neighbouring columns of cells and
    /// reads each plane of sources around them once for the four columns (ILPV 16 cells, 4 a
    /// column; LPV the 12 its face neighbours need, 3 a column), with no shared memory and no
    /// barrier (for CPU devices, where every load is made lane by lane). LPV keeps the block of
    /// three planes around the bundle in registers and gathers from it; ILPV walks down as a
    /// stream, adding each plane to the partial sums of the bundle's cells it is a source of.
    /// Where columns are not split, a thread does not read the planes past the lattice (ILPV's
    /// stream: nor add them; LPV's block: the one below).
    Column,
    /// The column kernel with one column a thread: more cells read a column (ILPV 9, LPV 5),
    /// fewer to keep (on lavapipe, faster for some lattices: the autotune measures it).
    SingleColumn,
    /// The single column whose threads share each row's cells across the subgroup: a thread
    /// reads its own column's cell of a row and takes the cells at x ± 1 from the lanes beside
    /// it, the subgroup's two ends from one read more (ILPV 4 cells read a plane instead of 9,
    /// LPV 4 instead of 5). For CPU devices with subgroup shuffles, whose lanes lie along x
    /// ([`shared_rows_fit`]).
    SharedRows,
}

impl Kernel {
    /// Every kernel, in the order `--kernel` lists them.
    pub const ALL: [Kernel; 5] = [
        Kernel::Tiled,
        Kernel::Naive,
        Kernel::Column,
        Kernel::SingleColumn,
        Kernel::SharedRows,
    ];

    /// Whether the kernel reads its source lattice, the geometry and the accumulation as texel
    /// buffers.
    pub fn reads_texels(self) -> bool {
        self.column_bundle().is_some()
    }

    /// The kernel's name on the command line (`--kernel`).
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Tiled => "tiled",
            Kernel::Naive => "naive",
            Kernel::Column => "column",
            Kernel::SingleColumn => "single-column",
            Kernel::SharedRows => "shared-rows",
        }
    }

    /// Whether `gpu` can run the kernel with workgroups of some width (the shared rows where
    /// [`shared_rows_possible`]; every other kernel anywhere).
    pub fn runs_on(self, gpu: &Gpu) -> bool {
        self != Kernel::SharedRows || shared_rows_possible(gpu)
    }

    /// The side of the square bundle of columns a thread of a column kernel walks.
    pub fn column_bundle(self) -> Option<u32> {
        match self {
            Kernel::Column => Some(2),
            Kernel::SingleColumn | Kernel::SharedRows => Some(1),
            Kernel::Tiled | Kernel::Naive => None,
        }
    }
}

/// How a propagation step's dispatches carry the three colour channels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ChannelPlan {
    /// A dispatch per channel: three independent parts, which run in sequence on one queue or
    /// overlap on a compute queue each (`--parts async`).
    Separate,
    /// R, G and B in one dispatch (one part): the geometry is read, and the blocking evaluated,
    /// once for all three.
    Fused,
}

/// How VPLs add into their cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Injection {
    /// Float atomics: a cell's sum depends on the order the threads add in, so runs (and the
    /// nodes of a CAVE) may differ in the last bits, and ILPV carries such differences on.
    Float,
    /// 64-bit fixed-point integer atomics, then one pass back to floats: the same bits on every
    /// run (seed 000 §11.4's deterministic injection).
    Fixed,
}

/// The far-field lattice of two-scale ILPV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum FarLattice {
    /// One lattice.
    Off,
    /// Cells of [`super::two_scale::FAR_CELL_IN_FREE_PATHS`] of the scene's mean free path.
    Auto,
    /// This many cells along the scene's longest axis.
    Cells(u32),
}

impl Default for LpvSettings {
    fn default() -> Self {
        LpvSettings {
            scheme: Scheme::Ilpv,
            lattice: DEFAULT_LATTICE,
            iterations: DEFAULT_ITERATIONS,
            incremental: DEFAULT_INCREMENTAL,
            rsm: DEFAULT_RSM,
            absorption: 0.0,
            scattering: 0.0,
            extinction: Extinction::Physical,
            blocking_lobe: BlockingLobe::TwoSided,
            blocking_strength: 1.0,
            first_step_unblocked: true,
            kernel: None,
            channels: None,
            cell_order: None,
            clamp_compensation: true,
            ilpv_lookup: IlpvLookup::Accumulated,
            inject_offset: DEFAULT_INJECT_OFFSET,
            inject_toward: InjectToward::Normal,
            injection: Injection::Float,
            lookup_offset: DEFAULT_LOOKUP_OFFSET,
            lookup_resolution: LookupResolution::Full,
            lookup_filter: None,
            far_lattice: FarLattice::Auto,
            near_steps: DEFAULT_NEAR_STEPS,
            far_injection: DEFAULT_FAR_INJECTION,
        }
    }
}

impl LpvSettings {
    pub(super) fn validate(&self) -> Result<(), InputError> {
        let err = |m: String| Err(InputError::new(m));
        if self.iterations > 4096 {
            return err(format!(
                "--iterations {} is out of range 0..=4096",
                self.iterations
            ));
        }
        if !(self.incremental.is_finite() && (0.0..=0.999).contains(&self.incremental)) {
            return err(format!(
                "--incremental {} is out of range [0, 0.999]",
                self.incremental
            ));
        }
        if !(self.blocking_strength.is_finite() && (0.0..=16.0).contains(&self.blocking_strength)) {
            return err(format!(
                "--blocking-strength {} is out of range [0, 16]",
                self.blocking_strength
            ));
        }
        if !(8..=2048).contains(&self.rsm) {
            return err(format!("--rsm {} is out of range 8..=2048", self.rsm));
        }
        for (name, v) in [
            ("--absorption", self.absorption),
            ("--scattering", self.scattering),
        ] {
            let max = if self.extinction == Extinction::Thesis {
                1.0
            } else {
                1e6
            };
            if !(v.is_finite() && (0.0..=max).contains(&v)) {
                return err(format!("{name} {v} is out of range [0, {max}]"));
            }
        }
        Ok(())
    }

    /// The settings two scales add (checked where two scales run).
    pub(super) fn validate_two_scale(&self) -> Result<(), InputError> {
        let err = |m: String| Err(InputError::new(m));
        if self.ilpv_lookup == IlpvLookup::Final {
            return err(
                "--far-lattice needs --ilpv-lookup accumulated (the final lattice cannot leave out the near field's steps)".into(),
            );
        }
        if self.near_steps == 0 || self.near_steps > 64 {
            return err(format!(
                "--near-steps {} is out of range 1..=64",
                self.near_steps
            ));
        }
        if !(self.far_injection.is_finite() && (0.0..=1.0).contains(&self.far_injection)) {
            return err(format!(
                "--far-injection {} is out of range [0, 1]",
                self.far_injection
            ));
        }
        Ok(())
    }

    fn reads_final(&self) -> bool {
        self.scheme == Scheme::Ilpv && self.ilpv_lookup == IlpvLookup::Final
    }

    /// Whether the light of a frame's last step goes on: carried into the next frame (ILPV at
    /// λ_incr above 0) or looked up alone (ILPV's final lookup).
    fn last_result_read(&self) -> bool {
        self.scheme == Scheme::Ilpv && (self.incremental > 0.0 || self.reads_final())
    }

    /// Steps recorded per frame: all of them, but for accumulated ILPV at λ_incr 0 one fewer,
    /// since the last step's result is neither looked up nor carried (a two-scale near field of
    /// 2 steps runs 1).
    pub(super) fn steps_run(&self) -> usize {
        let steps = self.iterations as usize;
        match self.scheme {
            Scheme::Ilpv if !self.last_result_read() => steps.saturating_sub(1),
            _ => steps,
        }
    }

    /// How the lookup reads the lattices on `gpu`: `lookup_filter`, or
    /// [`LookupFilter::for_device`].
    pub(super) fn lookup_filter_on(&self, gpu: &Gpu) -> LookupFilter {
        self.lookup_filter
            .unwrap_or_else(|| LookupFilter::for_device(gpu))
    }

    /// How the lattices' buffers hold their cells on `gpu`, whose step walks whole columns or
    /// not, read with `filter`: `cell_order`, or [`CellOrder::for_step`].
    fn cell_order_on(
        &self,
        gpu: &Gpu,
        whole_columns: bool,
        filter: LookupFilter,
    ) -> Result<CellOrder, InputError> {
        let copied_to_images = filter == LookupFilter::Sampler;
        match self.cell_order {
            Some(CellOrder::Columns) if copied_to_images => Err(InputError::new(
                "--cell-order columns needs the lookup to read texels (--lookup-filter texels or shared-texels; the sampler's 3-D images are copied from the lattices row by row)",
            )),
            Some(order) => Ok(order),
            None => Ok(CellOrder::for_step(gpu.info.is_cpu(), whole_columns, copied_to_images)),
        }
    }

    /// Whether anything reads a step's result lattice (a later step, the next frame or the
    /// lookup): not where one step runs a frame and its light only goes into the accumulation
    /// (a two-scale near field at its default 2 steps, classic LPV of one step), whose step
    /// then writes the accumulation alone.
    pub(super) fn step_results_read(&self) -> bool {
        self.steps_run() > 1 || self.last_result_read()
    }

    /// Whether ILPV's steps store their results compensated for the next step (the clamp
    /// compensation of every source but a frame's first, which has its own pass): where the
    /// compensation is on and a step follows another within a frame.
    pub(super) fn steps_compensate_results(&self) -> bool {
        self.scheme == Scheme::Ilpv && self.clamp_compensation && self.steps_run() > 1
    }

    /// Whether step `step` (from 0) of a frame blocks light: every one but a frame's first,
    /// which the thesis leaves unblocked (`--block-first-step` blocks it too).
    pub(super) fn step_blocks(&self, step: usize) -> bool {
        step > 0 || !self.first_step_unblocked
    }

    /// What an ILPV step does besides transport, for its cost.
    pub(super) fn step_work(&self) -> StepWork {
        if self.step_applies_medium() {
            StepWork::AppliesMedium
        } else if self.steps_compensate_results() {
            StepWork::TransportsAndCompensates
        } else {
            StepWork::Transports
        }
    }

    /// Whether the ILPV step applies the medium (absorption and scattering) itself: not with
    /// clamp compensation, which applies it before the step, nor without a medium (both
    /// coefficients 0, which [`LpvSettings::medium`] turns into zero at every cell size).
    pub(super) fn step_applies_medium(&self) -> bool {
        self.scheme == Scheme::Ilpv
            && !self.clamp_compensation
            && (self.absorption > 0.0 || self.scattering > 0.0)
    }

    /// Lattice-normalised (λa, λs), clamped so that λa + λs ≤ 1.
    pub fn medium(&self, cell_size: f32) -> (f64, f64) {
        let d = MEAN_NEIGHBOUR_DISTANCE * f64::from(cell_size);
        let lambda = |sigma: f32| {
            let s = f64::from(sigma);
            match self.extinction {
                Extinction::Thesis if s <= 0.0 => 0.0,
                Extinction::Thesis => s.powf(d),
                Extinction::Physical => 1.0 - (-s * d).exp(),
            }
        };
        let (a, s) = (lambda(self.absorption), lambda(self.scattering));
        let total = a + s;
        if total > 1.0 {
            (a / total, s / total)
        } else {
            (a, s)
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuNeighbour {
    transfer: [f32; 4],
    offset: [i32; 3],
    outscatter: f32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuFace {
    evaluation: [f32; 4],
    lobe: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuAxis {
    offset: [i32; 4],
    blocking_transfer: [f32; 4],
    faces: [GpuFace; 5],
}

crate::push_constants! {
    struct InjectPush {
        origin_cell: [f32; 4],
        dims: [i32; 4],
        layers: u32,
        offset: f32,
        toward_light: u32,
        scale: f32,
    }
}

crate::push_constants! {
    struct ResolvePush {
        cells: u32,
        inverse_scale: f32,
    }
}

crate::push_constants! {
    struct MergePush {
        /// Per channel of the part (R or its one channel first).
        previous_factor: [f32; 4],
        current_factor: [f32; 4],
        cells: u32,
    }
}

crate::push_constants! {
    struct CompensatePush {
        count: u32,
        keep_dc: f32,
        keep_directional: f32,
    }
}

crate::push_constants! {
    struct IlpvPush {
        dims: [i32; 4],
        keep: f32,
        scatter_energy: f32,
        accumulate: u32,
        keep_dc: f32,
        keep_directional: f32,
        compensate_result: u32,
    }
}

crate::push_constants! {
    struct LpvPush {
        dims: [i32; 4],
    }
}

/// Workgroup tiles the tiled kernels try, largest first; the first whose halo-padded light and
/// geometry tiles fit the device's shared memory is used.
const TILE_CANDIDATES: [[u32; 3]; 6] = [
    [8, 8, 8],
    [8, 8, 4],
    [8, 4, 4],
    [4, 4, 4],
    [4, 4, 2],
    [2, 2, 2],
];
/// Cells of padding on the innermost (z) axis of the shared tiles.
const Z_PAD: u32 = 1;
/// Workgroup of the naive kernels.
const NAIVE_GROUP: [u32; 3] = [4, 4, 4];
/// Threads in a workgroup of the column kernels ([`column_group`]): one per bundle of columns
/// ([`Kernel::column_bundle`]), each stepping through [`column_cells`] cells along z.
const COLUMN_THREADS: u32 = 64;
/// Bundles a column kernel's workgroup spans along x at most.
const COLUMN_GROUP_WIDEST: u32 = 32;
/// Workgroups a column kernel's dispatch should have at least, to keep every core busy.
const COLUMN_MIN_WORKGROUPS: u32 = 8;

/// The workgroup of a column kernel walking bundles of `bundle`² columns in a lattice of
/// `dims`: [`COLUMN_THREADS`] threads spanning as many bundles along x as the lattice has (a
/// power of two from 8 to [`COLUMN_GROUP_WIDEST`]), so that in each plane its SIMD batches read
/// long runs of contiguous cells (on lavapipe a 64³ lattice's step takes 12-18% less time than
/// in workgroups of 8x8; docs/performance.md).
pub fn column_group(dims: [u32; 3], bundle: u32) -> [u32; 3] {
    let x = column_bundles(dims, bundle)[0].next_power_of_two().clamp(8, COLUMN_GROUP_WIDEST);
    [x, COLUMN_THREADS / x, 1]
}

/// Cells along z each thread of a column kernel walking bundles of `bundle`² columns propagates
/// in a lattice of `dims` cells: the whole column (the two planes it starts with are loaded once
/// per column, not per step) unless that leaves fewer than [`COLUMN_MIN_WORKGROUPS`]
/// workgroups, then the column split evenly.
pub fn column_cells(dims: [u32; 3], bundle: u32) -> u32 {
    let [x, y] = column_bundles(dims, bundle);
    let [group_x, group_y, _] = column_group(dims, bundle);
    let across = x.div_ceil(group_x) * y.div_ceil(group_y);
    let pieces = COLUMN_MIN_WORKGROUPS.div_ceil(across).min(dims[2]);
    dims[2].div_ceil(pieces)
}

/// The column kernels' shape, for the autotune's cache key: a change to the bundle, the
/// workgroup or the split of a column makes the cached timings stale, as a change to their
/// SPIR-V does.
pub fn column_shape() -> String {
    let mut bundles: Vec<String> = Kernel::ALL
        .iter()
        .filter_map(|kernel| kernel.column_bundle())
        .map(|side| format!("{side}x{side}"))
        .collect();
    bundles.dedup();
    format!(
        "column bundles {}, {COLUMN_THREADS} threads up to {COLUMN_GROUP_WIDEST} wide, {COLUMN_MIN_WORKGROUPS} workgroups at least",
        bundles.join(" and ")
    )
}

/// Bundles of `bundle`² columns a column kernel's threads take across x and y of a lattice of
/// `dims`.
fn column_bundles(dims: [u32; 3], bundle: u32) -> [u32; 2] {
    [dims[0].div_ceil(bundle), dims[1].div_ceil(bundle)]
}

/// Shared memory a tile of `t` cells needs: light (one word per cell and channel) and
/// `geometry_words` words of geometry per cell, one-cell halo, z padded.
pub fn tile_shared_bytes(t: [u32; 3], geometry_words: u32, channels: u32) -> u32 {
    (channels + geometry_words) * 16 * (t[0] + 2) * (t[1] + 2) * (t[2] + 2 + Z_PAD)
}

/// The largest candidate tile of `channels` channels that fits `shared_bytes` and
/// `max_invocations`.
pub fn choose_tile(
    shared_bytes: u32,
    max_invocations: u32,
    geometry_words: u32,
    channels: u32,
) -> Option<[u32; 3]> {
    TILE_CANDIDATES.into_iter().find(|t| {
        tile_shared_bytes(*t, geometry_words, channels) <= shared_bytes
            && t.iter().product::<u32>() <= max_invocations
    })
}

/// The widest subgroup whose VPLs the injection sums per cell before its atomics, on a CPU
/// device (every lane visits every lane; each float atomic is a loop over the lanes there).
const MAX_SUMMED_SUBGROUP: u32 = 16;

/// The injection's SPIR-V, its specialisation and its description, for `injection` on `gpu`:
/// float atomics summed per cell across each subgroup first on a CPU device whose subgroups
/// shuffle, are at most [`MAX_SUMMED_SUBGROUP`] lanes and divide the workgroup (the sums read
/// every lane of a subgroup), else one atomic a VPL; or the fixed-point kernel.
fn injection_kernel(
    gpu: &Gpu,
    injection: Injection,
) -> (&'static [u8], Specialization, &'static str) {
    let info = &gpu.info;
    let lanes = info.subgroup_size;
    let workgroup = crate::shader_shared::IMAGE_WORKGROUP.pow(2);
    let sums_subgroups = info.is_cpu()
        && info.compute_subgroup_shuffles
        && (2..=MAX_SUMMED_SUBGROUP).contains(&lanes)
        && workgroup.is_multiple_of(lanes);
    match injection {
        Injection::Float if sums_subgroups => (
            shaders::GI_LPV_INJECT_SUBGROUP_COMP,
            Specialization::new().with_u32(0, lanes),
            "float atomics, each subgroup's VPLs summed per cell first",
        ),
        Injection::Float => (
            shaders::GI_LPV_INJECT_COMP,
            Specialization::new(),
            "float atomics, one a VPL",
        ),
        Injection::Fixed => (
            shaders::GI_LPV_INJECT_FIXED_COMP,
            Specialization::new(),
            "64-bit fixed-point atomics (the same bits whatever the order)",
        ),
    }
}

/// The SPIR-V of a propagation step.
pub fn propagation_spirv(scheme: Scheme, kernel: Kernel, plan: ChannelPlan) -> &'static [u8] {
    use ChannelPlan::{Fused, Separate};
    match (scheme, kernel, plan) {
        (Scheme::Ilpv, Kernel::Tiled, Separate) => shaders::GI_LPV_ILPV_TILED_COMP,
        (Scheme::Ilpv, Kernel::Tiled, Fused) => shaders::GI_LPV_ILPV_TILED_RGB_COMP,
        (Scheme::Ilpv, Kernel::Naive, Separate) => shaders::GI_LPV_ILPV_NAIVE_COMP,
        (Scheme::Ilpv, Kernel::Naive, Fused) => shaders::GI_LPV_ILPV_NAIVE_RGB_COMP,
        (Scheme::Ilpv, Kernel::Column | Kernel::SingleColumn, Separate) => {
            shaders::GI_LPV_ILPV_COLUMN_COMP
        }
        (Scheme::Ilpv, Kernel::Column | Kernel::SingleColumn, Fused) => {
            shaders::GI_LPV_ILPV_COLUMN_RGB_COMP
        }
        (Scheme::Lpv, Kernel::Tiled, Separate) => shaders::GI_LPV_LPV_TILED_COMP,
        (Scheme::Lpv, Kernel::Tiled, Fused) => shaders::GI_LPV_LPV_TILED_RGB_COMP,
        (Scheme::Lpv, Kernel::Naive, Separate) => shaders::GI_LPV_LPV_NAIVE_COMP,
        (Scheme::Lpv, Kernel::Naive, Fused) => shaders::GI_LPV_LPV_NAIVE_RGB_COMP,
        (Scheme::Lpv, Kernel::Column | Kernel::SingleColumn, Separate) => {
            shaders::GI_LPV_LPV_COLUMN_COMP
        }
        (Scheme::Lpv, Kernel::Column | Kernel::SingleColumn, Fused) => {
            shaders::GI_LPV_LPV_COLUMN_RGB_COMP
        }
        (Scheme::Ilpv, Kernel::SharedRows, Separate) => shaders::GI_LPV_ILPV_SHARED_ROWS_COMP,
        (Scheme::Ilpv, Kernel::SharedRows, Fused) => shaders::GI_LPV_ILPV_SHARED_ROWS_RGB_COMP,
        (Scheme::Lpv, Kernel::SharedRows, Separate) => shaders::GI_LPV_LPV_SHARED_ROWS_COMP,
        (Scheme::Lpv, Kernel::SharedRows, Fused) => shaders::GI_LPV_LPV_SHARED_ROWS_RGB_COMP,
    }
}

/// Whether the shared-rows kernel's assumption holds for workgroups `group_x` invocations wide on
/// `gpu`: a CPU device (lavapipe, whose subgroups are runs of consecutive
/// invocations) with subgroup shuffles in compute shaders, subgroups of at least 8 lanes (an
/// ILPV plane's 6 ends are read one a lane) and a whole number of them across the workgroup,
/// so that each subgroup's lanes lie along one row in x.
pub fn shared_rows_fit(gpu: &Gpu, group_x: u32) -> bool {
    shared_rows_possible(gpu) && group_x.is_multiple_of(gpu.info.subgroup_size)
}

/// `kernel` where it can run on `gpu` for `lattice`. The shared rows need workgroups a whole
/// number of subgroups wide ([`shared_rows_fit`]): pinned (`pinned`, `--kernel shared-rows`)
/// where they are not, an error; chosen by the autotune (whose cache holds a lattice size, not
/// a scene's lattice), the single column, which gives the same bits.
fn shared_rows_or_single_column(
    gpu: &Gpu,
    kernel: Kernel,
    pinned: Option<Kernel>,
    lattice: &Lattice,
) -> anyhow::Result<Kernel> {
    let width = column_group(lattice.dims.to_array(), 1)[0];
    if kernel != Kernel::SharedRows || shared_rows_fit(gpu, width) {
        return Ok(kernel);
    }
    match pinned {
        Some(_) => Err(InputError::new(format!(
            "--kernel shared-rows needs a CPU device with subgroup shuffles in compute shaders, and workgroups a whole number of subgroups wide (this device: {}, subgroups of {}, shuffles {}; this lattice's workgroups {width} wide)",
            gpu.info.type_name(),
            gpu.info.subgroup_size,
            gpu.info.compute_subgroup_shuffles,
        ))
        .into()),
        None => Ok(Kernel::SingleColumn),
    }
}

/// Whether `gpu` can run the shared-rows kernel with workgroups of some width
/// ([`shared_rows_fit`] without the width).
pub fn shared_rows_possible(gpu: &Gpu) -> bool {
    let info = &gpu.info;
    info.is_cpu() && info.compute_subgroup_shuffles && info.subgroup_size >= 8
}

/// The blend's bindings for channel `i` of a part: the lattice it writes, this frame's and last
/// frame's.
fn merge_bindings<'a>(
    i: usize,
    target: &'a Buffer,
    current: &'a Buffer,
    previous: &'a Buffer,
) -> [Binding<'a>; 3] {
    const TARGETS: [u32; 3] = [ids::MERGE_TARGET_R, ids::MERGE_TARGET_G, ids::MERGE_TARGET_B];
    const CURRENTS: [u32; 3] = [ids::MERGE_CURRENT_R, ids::MERGE_CURRENT_G, ids::MERGE_CURRENT_B];
    const PREVIOUS: [u32; 3] = [ids::MERGE_PREVIOUS_R, ids::MERGE_PREVIOUS_G, ids::MERGE_PREVIOUS_B];
    [
        Binding::write(TARGETS[i], target),
        Binding::read(CURRENTS[i], current),
        Binding::read(PREVIOUS[i], previous),
    ]
}

/// The SPIR-V of ILPV's blend for a channel plan.
pub fn merge_spirv(plan: ChannelPlan) -> &'static [u8] {
    match plan {
        ChannelPlan::Separate => shaders::GI_LPV_MERGE_COMP,
        ChannelPlan::Fused => shaders::GI_LPV_MERGE_RGB_COMP,
    }
}

/// The SPIR-V of ILPV's clamp compensation for a channel plan, reading texels where the
/// kernel's lattices have texel views.
pub fn compensate_spirv(plan: ChannelPlan, texels: bool) -> &'static [u8] {
    match (plan, texels) {
        (ChannelPlan::Separate, false) => shaders::GI_LPV_COMPENSATE_COMP,
        (ChannelPlan::Separate, true) => shaders::GI_LPV_COMPENSATE_TEXELS_COMP,
        (ChannelPlan::Fused, false) => shaders::GI_LPV_COMPENSATE_RGB_COMP,
        (ChannelPlan::Fused, true) => shaders::GI_LPV_COMPENSATE_RGB_TEXELS_COMP,
    }
}

/// The colour channels: the method's independent parts when each has its own dispatches.
const CHANNELS: [&str; 3] = ["R", "G", "B"];
/// The one part of a plan that carries the three channels together.
const ALL_CHANNELS: [&str; 1] = ["RGB"];

impl ChannelPlan {
    /// Colour channels one propagation dispatch carries.
    pub fn channels(self) -> u32 {
        match self {
            ChannelPlan::Separate => 1,
            ChannelPlan::Fused => 3,
        }
    }
}

/// The geometry lattice's last update after geometry moved.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GeometryUpdate {
    /// Cells rebuilt, of `cells` in the lattice.
    pub rebuilt: usize,
    pub cells: usize,
    /// CPU time of the rebuild.
    pub milliseconds: f64,
}

pub struct Lpv {
    pub settings: LpvSettings,
    pub lattice: Lattice,
    /// How the GPU buffers hold the lattice's cells ([`CellOrder::for_step`] unless pinned).
    cell_order: CellOrder,
    pub transfer: TransferVectors,
    /// The propagation kernel that runs and how its dispatches carry the channels, and the
    /// autotune's reasons when it chose them.
    pub(crate) kernel: Kernel,
    pub(crate) plan: ChannelPlan,
    autotune: Option<autotune::Choice>,
    /// The workgroup tile of the propagation kernel (tiled: the shared-memory tile).
    pub tile: [u32; 3],
    /// Threads of each propagation dispatch.
    propagate_threads: [u32; 3],
    inject_pipeline: ComputePipeline,
    /// How the injection adds VPLs to their cells, for the description.
    injection_kernel: &'static str,
    /// The fixed-point injection's sums and the pass back to floats (`Injection::Fixed`).
    fixed: Option<FixedInjection>,
    merge_pipeline: ComputePipeline,
    compensate_pipeline: ComputePipeline,
    step_pipelines: StepPipelines,
    /// The lookup pass of a lattice looked up on its own (None: two scales look up both of
    /// theirs in one pass).
    lookup: Option<Lookup>,
    /// How the lookup reads this lattice.
    pub(super) lookup_filter: LookupFilter,
    /// With [`LookupFilter::Sampler`], what the lookup samples: per channel, a copy of its
    /// result lattice as a 3-D image inside a border of `LOOKUP_BORDER` zero cells, read with
    /// the sampler's trilinear filter (one fetch instead of eight). None: the lookup reads the
    /// result lattices as texels.
    lookup_images: Option<[Image; 3]>,
    /// The reflective shadow maps it injects from (None: a far field reads its near field's).
    rsm: Option<Rsm>,
    /// The propagation pass's name in the profile.
    propagate_pass: &'static str,
    field: Field,
    /// Two lattices per channel, ping-ponged.
    lattices: [[Buffer; 2]; 3],
    /// The sum of the steps the lookup reads, per channel.
    accumulation: [Buffer; 3],
    /// The last injection, per channel, kept for the frames whose lights and geometry did not
    /// change: they copy it instead of rendering the RSM and injecting again.
    injected: [Buffer; 3],
    /// `injected` holds the injection of the lights and geometry as they are.
    injection_kept: bool,
    /// This frame copies `injected` instead of injecting (decided by `begin_frame`).
    reuses_injection: bool,
    geometry: Buffer,
    neighbours: Buffer,
    axes: Buffer,
    /// Rebuilt runs of the geometry lattice (rows or columns, as its buffer holds them) to write
    /// at the next frame: (byte offset, words).
    pending_geometry: Vec<(u64, Vec<u8>)>,
    geometry_update: Option<GeometryUpdate>,
    /// Which of the two lattices per channel holds the last frame's propagated light.
    result: usize,
    /// This frame's injection target, and where its channels left their results.
    current: usize,
    pending_result: usize,
    frames: u64,
    /// Frames since the lights last changed (for the convergence of the ILPV blend).
    frames_since_change: u64,
    /// Emitted flux per colour channel of the lights at the last frame and at this one (E in the
    /// ILPV blend, per channel so that a recoloured light scales each channel's carried light).
    previous_energy: [f64; 3],
    energy: [f64; 3],
    device_shared_bytes: u32,
}

/// What the deterministic injection adds to a lattice: 64-bit sums per coefficient and channel,
/// and the pass that turns them into the lattice's floats.
struct FixedInjection {
    sums: [Buffer; 3],
    resolve: ComputePipeline,
}

/// Accumulator units per unit of light for a frame whose lights emit `flux` per channel: the
/// power of two that puts the whole emitted flux at 2^54 units or less. A cell's VPLs reflect
/// at most the light that reached them, and a coefficient of the lobe Φ/π SH_cos(n) is at most
/// 0.33 Φ, so no cell can come near the 2^63 an i64 holds; the exact power of two makes the
/// sums' conversion back (sum × 2^-k) exact but for the final rounding to float.
pub fn fixed_point_scale(flux: [f64; 3]) -> f32 {
    let bound = flux.iter().fold(0.0f64, |m, &f| m.max(f.abs()));
    if !(bound.is_finite() && bound > 0.0) {
        return 1.0;
    }
    let exponent = (54.0 - bound.log2()).floor().clamp(-100.0, 100.0);
    2f64.powf(exponent) as f32
}

/// Refuse a lattice the lookup cannot read on this device with `filter`: one past the 3-D image
/// size or without linear filtering of RGBA32F for the sampler, one past the texel-buffer size
/// for texels. `kernel_texels`: the propagation reads the lattices as texels too (then the
/// sampler does not lift the texel-buffer limit).
fn check_lookup_limits(
    gpu: &Gpu,
    filter: LookupFilter,
    lattice: &Lattice,
    kernel_texels: bool,
) -> anyhow::Result<()> {
    let [x, y, z] = lattice.dims.to_array();
    match filter {
        LookupFilter::Sampler => {
            let side = lattice.dims.max_element() + 2 * LOOKUP_BORDER;
            if side > gpu.info.max_image_dimension_3d {
                return Err(InputError::new(format!(
                    "a {x}x{y}x{z} lattice exceeds the device's 3-D image limit of {} cells a side (the lookup samples the lattice as a 3-D image; --lookup-filter texels does not)",
                    gpu.info.max_image_dimension_3d
                ))
                .into());
            }
            if !gpu.supports_format(
                vk::Format::R32G32B32A32_SFLOAT,
                vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR,
            ) {
                anyhow::bail!(
                    "the LPV lookup filters RGBA32F 3-D images linearly, which this device cannot (no SAMPLED_IMAGE_FILTER_LINEAR for R32G32B32A32_SFLOAT; --lookup-filter texels does not)"
                );
            }
        }
        LookupFilter::SharedTexels if !LookupFilter::can_share_texels(gpu) => {
            return Err(InputError::new(format!(
                "--lookup-filter shared-texels needs subgroups of at least 8 lanes that ballot, vote and shuffle in fragment and compute shaders, which this device ({}) does not offer (--lookup-filter texels does not)",
                gpu.info.name
            ))
            .into());
        }
        LookupFilter::Texels | LookupFilter::SharedTexels => {
            let limit = gpu.info.max_texel_buffer_elements;
            if lattice.cell_count() > limit as usize {
                let instead = match kernel_texels {
                    true => "--lookup-filter sampler with --kernel tiled does not",
                    false => "--lookup-filter sampler does not",
                };
                return Err(InputError::new(format!(
                    "a {x}x{y}x{z} lattice exceeds the device's limit of {limit} texels in a texel buffer (the lookup reads the lattice as texels; {instead})"
                ))
                .into());
            }
        }
    }
    Ok(())
}

/// The lookup's 3-D images of a lattice (R, G, B) for the sampler, their border cleared to zero:
/// every frame copies the lattice into the cells inside it.
fn create_lookup_images(gpu: &Gpu, lattice: &Lattice) -> GpuResult<[Image; 3]> {
    let image = |c: usize| {
        gpu.create_image(&ImageDesc::new_3d(
            &format!("lookup lattice {}", CHANNELS[c]),
            vk::Format::R32G32B32A32_SFLOAT,
            (lattice.dims + 2 * LOOKUP_BORDER).to_array(),
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        ))
    };
    let images = [image(0)?, image(1)?, image(2)?];
    gpu.one_shot(|rec| {
        for image in &images {
            rec.clear_image("clear lookup lattice", image, [0.0; 4]);
        }
        Ok(())
    })?;
    Ok(images)
}

impl Lpv {
    /// One lattice of `settings` (whatever its `far_lattice`: two scales are
    /// [`super::two_scale::create`]'s).
    pub fn new(setup: &Setup, settings: LpvSettings) -> anyhow::Result<Lpv> {
        settings.validate()?;
        let mut lpv = Self::with_field(setup, settings, Field::Whole)?;
        let resolution = lpv.settings.lookup_resolution;
        let lookup = Lookup::new(
            setup.gpu,
            setup.scene,
            &[lpv.lookup_field()],
            resolution,
            lpv.lookup_filter,
        )?;
        lpv.lookup = Some(lookup);
        Ok(lpv)
    }

    /// The lookup of a lattice looked up on its own.
    fn own_lookup(&self) -> GpuResult<&Lookup> {
        self.lookup.as_ref().ok_or_else(|| {
            GpuError::Setup("a lattice of two scales is looked up by its two-scale owner".into())
        })
    }

    /// This lattice as the lookup reads it.
    pub fn lookup_field(&self) -> LookupField<'_> {
        let cell = self.lattice.cell_size;
        LookupField {
            lattices: match &self.lookup_images {
                Some(images) => LatticeReads::Images(images),
                None => LatticeReads::Texels(self.result_lattices()),
            },
            origin: self.lattice.origin,
            cell_size: cell,
            dims: self.dims(),
            cell_order: self.cell_order,
            scale: self.lookup_scale() / (std::f32::consts::PI * cell * cell),
            offset: self.settings.lookup_offset,
        }
    }

    /// One lattice of `field`'s part of the light (a far field gets no RSM of its own), with no
    /// lookup pass of its own: two scales look up both of theirs in one.
    pub(super) fn with_field(
        setup: &Setup,
        settings: LpvSettings,
        field: Field,
    ) -> anyhow::Result<Lpv> {
        let (gpu, scene) = (setup.gpu, setup.scene);
        let (kernel, plan, autotune) = match (settings.kernel, settings.channels) {
            (Some(kernel), Some(plan)) => (kernel, plan, None),
            (kernel, plan) => {
                let choice = autotune::choose(setup, &settings)?;
                (
                    kernel.unwrap_or(choice.kernel),
                    plan.unwrap_or(choice.plan),
                    Some(choice),
                )
            }
        };
        let channels = plan.channels();
        let lattice = Lattice::fit(scene.bounds_min, scene.bounds_max, settings.lattice)?;
        let kernel = shared_rows_or_single_column(gpu, kernel, settings.kernel, &lattice)?;
        let cells = lattice.cell_count();
        // The largest buffer: the geometry lattice (16 bytes per word, up to 4 words per cell)
        // or the fixed-point injection's sums (4 coefficients of 8 bytes per cell).
        let words = settings.blocking_lobe.words_per_cell();
        let fixed_bytes = if settings.injection == Injection::Fixed { 32 } else { 0 };
        let bytes_per_cell = (16 * words).max(fixed_bytes);
        let max_cells = gpu.info.max_storage_buffer_range as usize / bytes_per_cell;
        if cells > max_cells {
            return Err(InputError::new(format!(
                "a {}x{}x{} lattice ({cells} cells) exceeds the device's {max_cells}-cell buffer limit (its largest buffer holds {bytes_per_cell} bytes per cell: {words} geometry word(s) of 16{})",
                lattice.dims.x,
                lattice.dims.y,
                lattice.dims.z,
                if fixed_bytes > 0 { ", or the fixed-point sums' 32" } else { "" }
            ))
            .into());
        }
        let lookup_filter = settings.lookup_filter_on(gpu);
        check_lookup_limits(gpu, lookup_filter, &lattice, kernel.reads_texels())?;
        match settings.injection {
            Injection::Float if !gpu.info.shader_buffer_float32_atomic_add => anyhow::bail!(
                "LPV injection with float atomics needs VK_EXT_shader_atomic_float, which this device lacks (--injection fixed does not)"
            ),
            Injection::Fixed if !gpu.info.shader_buffer_int64_atomics => anyhow::bail!(
                "--injection fixed needs 64-bit integer atomics (shaderBufferInt64Atomics), which this device lacks"
            ),
            _ => {}
        }
        (setup.progress)("transfer vectors", 0.0);
        let transfer = TransferVectors::compute(TRANSFER_SAMPLES, TRANSFER_SEED);
        let faces = FaceScheme::compute();
        let strength = f64::from(settings.blocking_strength);
        (setup.progress)("geometry lattice", 0.5);
        let geometry_cells =
            geometry::build(&scene.mesh, &lattice, &transfer, settings.blocking_lobe)
                .scaled(strength);
        let geometry_words = settings.blocking_lobe.words_per_cell() as u32;
        (setup.progress)("geometry lattice", 1.0);

        let shared = gpu.info.max_shared_memory_bytes;
        let bundle = kernel.column_bundle();
        let tile = match (kernel, bundle) {
            (Kernel::Tiled, _) => choose_tile(
                shared,
                gpu.info.max_workgroup_invocations,
                geometry_words,
                channels,
            )
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "no propagation tile of {channels} channel(s) fits {shared} bytes of shared memory"
                )
            })?,
            (_, Some(bundle)) => column_group(lattice.dims.to_array(), bundle),
            (_, None) => NAIVE_GROUP,
        };
        let (inject_spirv, inject_spec, injection_kernel) =
            injection_kernel(gpu, settings.injection);
        // Cells a column kernel's thread walks (unused by the other kernels).
        let column = bundle.map_or(1, |bundle| column_cells(lattice.dims.to_array(), bundle));
        let whole_columns = bundle.is_some() && column >= lattice.dims.z;
        let cell_order = settings.cell_order_on(gpu, whole_columns, lookup_filter)?;
        let in_cell_order = |spec: Specialization| {
            spec.with_u32(ids::CELLS_IN_COLUMNS_CONSTANT, cell_order.columns_flag())
        };
        let inject_spec = in_cell_order(inject_spec);
        let propagate_spirv = propagation_spirv(settings.scheme, kernel, plan);
        let propagate_threads = propagation_threads(kernel, lattice.dims.to_array(), tile, column);
        let mut spec = in_cell_order(Specialization::new())
            .with_u32(0, tile[0])
            .with_u32(1, tile[1])
            .with_u32(2, tile[2])
            .with_u32(4, geometry_words)
            .with_u32(7, u32::from(settings.step_results_read()));
        if settings.scheme == Scheme::Ilpv {
            spec = spec
                .with_u32(8, u32::from(settings.step_applies_medium()))
                .with_u32(10, u32::from(settings.steps_compensate_results()));
        }
        match (kernel, bundle) {
            (Kernel::Tiled, _) => spec = spec.with_u32(3, Z_PAD),
            (_, Some(bundle)) => {
                spec = spec
                    .with_u32(5, column)
                    .with_u32(6, bundle)
                    .with_u32(9, u32::from(whole_columns));
            }
            (_, None) => {}
        }
        let none = Specialization::new();
        let propagate_name = match settings.scheme {
            Scheme::Ilpv => "ilpv propagation",
            Scheme::Lpv => "lpv propagation",
        };
        let step_pipeline = |blocks: bool| {
            let spec = spec.clone().with_u32(11, u32::from(blocks));
            ComputePipeline::new(gpu, propagate_name, propagate_spirv, &spec)
        };
        let first_blocks = settings.step_blocks(0);
        let later_differ = settings.steps_run() > 1 && settings.step_blocks(1) != first_blocks;
        let step_pipelines = StepPipelines {
            first: step_pipeline(first_blocks)?,
            later: later_differ.then(|| step_pipeline(!first_blocks)).transpose()?,
        };
        let rsm = match field {
            Field::Far => None,
            Field::Whole => Some(Rsm::new(gpu, scene, settings.rsm)?),
        };
        // The column kernel reads its sources (the lattices and the geometry) and the
        // accumulation as texel buffers.
        // So does the lookup, with --lookup-filter texels or shared-texels.
        let texels = kernel.reads_texels();
        let lattice_texels = texels || lookup_filter.reads_texels();
        let storage = |name: &str, bytes: usize, texels: bool| match texels {
            true => gpu.create_buffer(&BufferDesc::storage_texels(name, bytes as u64)),
            false => gpu.create_buffer(&BufferDesc::storage(name, bytes as u64)),
        };
        let lattice_buffer = |name: String| storage(&name, cells * 16, lattice_texels);
        let channel_pair = |c: usize| -> GpuResult<[Buffer; 2]> {
            Ok([
                lattice_buffer(format!("lattice {} a", CHANNELS[c]))?,
                lattice_buffer(format!("lattice {} b", CHANNELS[c]))?,
            ])
        };
        let lattices = [channel_pair(0)?, channel_pair(1)?, channel_pair(2)?];
        let lookup_images = match lookup_filter {
            LookupFilter::Sampler => Some(create_lookup_images(gpu, &lattice)?),
            LookupFilter::Texels | LookupFilter::SharedTexels => None,
        };
        let fixed = match settings.injection {
            Injection::Float => None,
            Injection::Fixed => {
                let sums = |c: usize| {
                    let name = format!("fixed-point injection {}", CHANNELS[c]);
                    gpu.create_buffer(&BufferDesc::storage(&name, (cells * 4 * 8) as u64))
                };
                Some(FixedInjection {
                    sums: [sums(0)?, sums(1)?, sums(2)?],
                    resolve: ComputePipeline::new(
                        gpu,
                        "inject resolve",
                        shaders::GI_LPV_INJECT_RESOLVE_COMP,
                        &none,
                    )?,
                })
            }
        };
        let accumulation = [
            lattice_buffer("accumulation R".into())?,
            lattice_buffer("accumulation G".into())?,
            lattice_buffer("accumulation B".into())?,
        ];
        // Only copied to and from the lattices: no texel view.
        let kept_injection = |c: usize| {
            storage(&format!("kept injection {}", CHANNELS[c]), cells * 16, false)
        };
        let injected = [kept_injection(0)?, kept_injection(1)?, kept_injection(2)?];
        let geometry_f32 = cell_order.from_rows(
            lattice.dims,
            &geometry_cells.to_f32(),
            geometry_words as usize,
        );
        let neighbours: Vec<GpuNeighbour> = transfer
            .neighbours
            .iter()
            .map(|n| GpuNeighbour {
                transfer: n.transfer.as_vec4().to_array(),
                offset: n.offset.to_array(),
                outscatter: n.outscatter as f32,
            })
            .collect();
        let axes: Vec<GpuAxis> = faces
            .axes
            .iter()
            .map(|(axis, f)| GpuAxis {
                offset: [axis.x, axis.y, axis.z, 0],
                blocking_transfer: transfer
                    .neighbours
                    .iter()
                    .find(|n| n.offset == *axis)
                    .map_or(DVec4::ZERO, |n| n.transfer)
                    .as_vec4()
                    .to_array(),
                faces: f.map(|face| GpuFace {
                    evaluation: (sh::basis(face.direction) * face.solid_angle)
                        .as_vec4()
                        .to_array(),
                    lobe: (sh::cosine_lobe(face.normal) / std::f64::consts::PI)
                        .as_vec4()
                        .to_array(),
                }),
            })
            .collect();

        Ok(Lpv {
            lattice,
            cell_order,
            transfer,
            kernel,
            plan,
            autotune,
            tile,
            propagate_threads,
            inject_pipeline: ComputePipeline::new(gpu, "inject", inject_spirv, &inject_spec)?,
            injection_kernel,
            fixed,
            merge_pipeline: ComputePipeline::new(gpu, "merge", merge_spirv(plan), &none)?,
            compensate_pipeline: ComputePipeline::new(
                gpu,
                "compensate",
                compensate_spirv(plan, texels),
                &none,
            )?,
            step_pipelines,
            lookup: None,
            lookup_filter,
            lookup_images,
            rsm,
            propagate_pass: match field {
                Field::Whole => PROPAGATE,
                Field::Far => FAR_PROPAGATE,
            },
            field,
            lattices,
            accumulation,
            injected,
            injection_kept: false,
            reuses_injection: false,
            geometry: {
                let bytes: &[u8] = bytemuck::cast_slice(&geometry_f32);
                let buffer = storage("geometry lattice", bytes.len(), texels)?;
                gpu.write_buffer(&buffer, bytes)?;
                buffer
            },
            neighbours: gpu.upload_uniform("ilpv neighbours", bytemuck::cast_slice(&neighbours))?,
            axes: gpu.upload_uniform("lpv axes", bytemuck::cast_slice(&axes))?,
            pending_geometry: Vec::new(),
            geometry_update: None,
            result: 0,
            current: 0,
            pending_result: 0,
            frames: 0,
            frames_since_change: 0,
            previous_energy: [0.0; 3],
            energy: emitted_flux(&scene.raster_lights()),
            device_shared_bytes: shared,
            settings,
        })
    }

    /// The lattices the lookup reads: the accumulation, or ILPV's last propagated light.
    pub fn result_lattices(&self) -> [&Buffer; 3] {
        [0, 1, 2].map(|c| self.looked_up(c, self.result))
    }

    /// Channel `channel`'s lattice the lookup reads when `result` holds the propagated light.
    fn looked_up(&self, channel: usize, result: usize) -> &Buffer {
        if self.settings.reads_final() {
            &self.lattices[channel][result]
        } else {
            &self.accumulation[channel]
        }
    }

    /// With the sampler's lookup, copy channel `channel`'s looked-up lattice into the 3-D image
    /// the lookup samples, inside its border.
    fn copy_to_lookup(&self, rec: &mut Recorder, channel: usize, result: usize) {
        let Some(images) = &self.lookup_images else {
            return;
        };
        let border = LOOKUP_BORDER as i32;
        rec.copy_buffer_to_box(
            "lattice to lookup image",
            self.looked_up(channel, result),
            &images[channel],
            [border; 3],
            self.lattice.dims.to_array(),
        );
    }

    fn geometry_words(&self) -> u32 {
        self.settings.blocking_lobe.words_per_cell() as u32
    }

    /// Whether step `step` (0-based) adds its result to the accumulation: every step for LPV;
    /// for ILPV every step but the last (whose light the next frame carries on).
    fn accumulates(&self, step: usize) -> bool {
        match self.settings.scheme {
            Scheme::Lpv => true,
            Scheme::Ilpv => {
                !self.settings.reads_final() && step + 1 < self.settings.iterations as usize
            }
        }
    }

    /// The lookup's scale (see [`IlpvLookup`]): ILPV's lattice holds the fresh light at weight
    /// 1 - λ_incr every frame, the first included.
    fn lookup_scale(&self) -> f32 {
        let fresh = 1.0 - self.settings.incremental;
        match (self.settings.scheme, self.settings.ilpv_lookup) {
            (Scheme::Lpv, _) => 1.0,
            (Scheme::Ilpv, IlpvLookup::Accumulated) => MEAN_NEIGHBOUR_DISTANCE as f32 / fresh,
            (Scheme::Ilpv, IlpvLookup::Final) => self.settings.iterations.max(1) as f32 / fresh,
        }
    }

    /// The ILPV blend weights (previous, current) of colour channel `channel` for this frame:
    /// λ̃a = λ_incr E_now / E_before (eq 3.4, per channel) and λ̃b = 1 - λ_incr. With nothing to
    /// carry (the first frame, or no light before) the carried lattice counts as empty, λ̃a = 0,
    /// and the fresh light still gets 1 - λ_incr: the lattice then grows through the recursion's
    /// partial sums up to its steady state instead of starting from a full-weight injection,
    /// which made frame 2 overshoot the settled light (4x at λ 0.99). Classic LPV: (0, 1).
    pub fn blend_weights(&self, channel: usize) -> (f32, f32) {
        let lambda = f64::from(self.settings.incremental);
        if self.settings.scheme != Scheme::Ilpv {
            return (0.0, 1.0);
        }
        let (now, before) = (self.energy[channel], self.previous_energy[channel]);
        let carried = if self.frames == 0 || before <= 0.0 {
            0.0
        } else {
            lambda * now / before
        };
        (carried as f32, (1.0 - lambda) as f32)
    }

    fn dims(&self) -> [i32; 4] {
        let d = self.lattice.dims.as_ivec3();
        [d.x, d.y, d.z, 0]
    }

    /// This frame's injection into the lattices of `self.current`: a copy of the kept one, or
    /// a new one from `rsm`, then kept.
    fn record_inject(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        rsm: &Rsm,
        views: u32,
    ) -> GpuResult<()> {
        let target = self.current;
        let lattices = [0, 1, 2].map(|c| &self.lattices[c][target]);
        let bytes = self.lattice.cell_count() as u64 * 16;
        if self.reuses_injection {
            let copies = [0, 1, 2].map(|c| (&self.injected[c], lattices[c], bytes));
            rec.copy_buffers("kept injection", &copies);
            return Ok(());
        }
        self.record_new_injection(rec, ctx, rsm, views, lattices)?;
        if self.injection_kept {
            let copies = [0, 1, 2].map(|c| (lattices[c], &self.injected[c], bytes));
            rec.copy_buffers("keep injection", &copies);
        }
        Ok(())
    }

    /// Inject this frame's VPLs from `rsm` into `lattices` (those of `self.current`).
    fn record_new_injection(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        rsm: &Rsm,
        views: u32,
        lattices: [&Buffer; 3],
    ) -> GpuResult<()> {
        // Float atomics add straight into the lattice; fixed point into its sums first.
        let [r, g, b] = match &self.fixed {
            None => lattices,
            Some(fixed) => [0, 1, 2].map(|c| &fixed.sums[c]),
        };
        let clear = match self.fixed {
            None => "clear lattice",
            Some(_) => "clear injection sums",
        };
        rec.fill_buffers(clear, &[(r, 0), (g, 0), (b, 0)]);
        let scale = fixed_point_scale(self.energy);
        let mut dims = self.dims();
        dims[3] = self.settings.rsm as i32;
        let o = self.lattice.origin;
        let push = InjectPush {
            origin_cell: [o.x, o.y, o.z, self.lattice.cell_size],
            dims,
            layers: views,
            offset: self.settings.inject_offset,
            toward_light: u32::from(self.settings.inject_toward == InjectToward::Light),
            scale,
        };
        rec.compute(&ComputePass {
            name: "inject",
            pipeline: &self.inject_pipeline,
            bindings: &[
                Binding::image_read(ids::INJECT_RSM_POSITION, &rsm.position),
                Binding::image_read(ids::INJECT_RSM_NORMAL, &rsm.normal),
                Binding::image_read(ids::INJECT_RSM_FLUX, &rsm.flux),
                Binding::write(ids::INJECT_LATTICE_R, r),
                Binding::write(ids::INJECT_LATTICE_G, g),
                Binding::write(ids::INJECT_LATTICE_B, b),
                Binding::read(ids::INJECT_VIEWS, &ctx.scene.shadow_views),
            ],
            push: &push,
            threads: [self.settings.rsm, self.settings.rsm, views],
        })?;
        let Some(fixed) = &self.fixed else {
            return Ok(());
        };
        let cells = self.lattice.cell_count() as u32;
        rec.compute(&ComputePass {
            name: "inject resolve",
            pipeline: &fixed.resolve,
            bindings: &[
                Binding::read(ids::RESOLVE_FIXED_R, r),
                Binding::read(ids::RESOLVE_FIXED_G, g),
                Binding::read(ids::RESOLVE_FIXED_B, b),
                Binding::write(ids::RESOLVE_LATTICE_R, lattices[0]),
                Binding::write(ids::RESOLVE_LATTICE_G, lattices[1]),
                Binding::write(ids::RESOLVE_LATTICE_B, lattices[2]),
            ],
            push: &ResolvePush {
                cells,
                inverse_scale: 1.0 / scale,
            },
            threads: [cells, 1, 1],
        })
    }

    /// Merge and propagate the colour channels `channels` (one part: one channel, or all three
    /// with a fused plan); returns the index of the lattice holding their result. `current`
    /// holds this frame's injection.
    fn merge_and_propagate(
        &self,
        rec: &mut Recorder,
        channels: &[usize],
        current: usize,
    ) -> GpuResult<usize> {
        self.record_merge(rec, channels, current)?;
        self.start_accumulation(rec, channels, current)?;
        self.record_steps(rec, channels, current)
    }

    /// Propagate `channels` from lattice `current`; returns the index of the lattice holding
    /// the last step's result.
    fn record_steps(
        &self,
        rec: &mut Recorder,
        channels: &[usize],
        current: usize,
    ) -> GpuResult<usize> {
        let (absorption, scattering) = self.settings.medium(self.lattice.cell_size);
        let mut src = current;
        for step in 0..self.settings.steps_run() {
            rec.in_step(step as u32 + 1, |rec| {
                self.record_step(rec, channels, step, src, (absorption, scattering))
            })?;
            src = 1 - src;
        }
        Ok(src)
    }

    /// Blend last frame's light of `channels` into this frame's injection (ILPV), in one
    /// dispatch, where the blend changes it.
    fn record_merge(&self, rec: &mut Recorder, channels: &[usize], current: usize) -> GpuResult<()> {
        let unchanged = channels.iter().all(|&c| self.blend_weights(c) == (0.0, 1.0));
        if unchanged {
            return Ok(());
        }
        self.record_blend(rec, channels, current, |c| {
            (&self.lattices[c][current], self.blend_weights(c))
        })
    }

    /// One blend pass over the lattice's cells for `channels`: per channel `c`, `target_of(c)`
    /// gives the lattice written and the (previous, current) factors by which lattices
    /// 1 - `current` and `current` are summed into it.
    fn record_blend<'s>(
        &'s self,
        rec: &mut Recorder,
        channels: &[usize],
        current: usize,
        target_of: impl Fn(usize) -> (&'s Buffer, (f32, f32)),
    ) -> GpuResult<()> {
        let [mut previous_factor, mut current_factor] = [[0.0f32; 4]; 2];
        let mut bindings = Vec::with_capacity(3 * channels.len());
        for (i, &channel) in channels.iter().enumerate() {
            let (target, factors) = target_of(channel);
            (previous_factor[i], current_factor[i]) = factors;
            let pair = &self.lattices[channel];
            bindings.extend(merge_bindings(i, target, &pair[current], &pair[1 - current]));
        }
        let cells = self.lattice.cell_count() as u32;
        rec.compute(&ComputePass {
            name: "merge",
            pipeline: &self.merge_pipeline,
            bindings: &bindings,
            push: &MergePush {
                previous_factor,
                current_factor,
                cells,
            },
            threads: [cells, 1, 1],
        })
    }

    /// Start the accumulation of `channels` with lattice `current` (a far field's: and the
    /// light it carries from last frame), unless the lookup reads the last step alone.
    fn start_accumulation(
        &self,
        rec: &mut Recorder,
        channels: &[usize],
        current: usize,
    ) -> GpuResult<()> {
        if self.settings.reads_final() {
            return Ok(());
        }
        match self.field {
            Field::Far => self.record_carried_start(rec, channels, current),
            Field::Whole => {
                let copies: Vec<_> = channels
                    .iter()
                    .map(|&c| {
                        let acc = &self.accumulation[c];
                        (&self.lattices[c][current], acc, acc.size)
                    })
                    .collect();
                rec.copy_buffers("accumulate", &copies);
                Ok(())
            }
        }
    }

    /// A far field's accumulation starts with the light carried from last frame, λ̃a times
    /// its last result, and the share `far_injection` (α) of this frame's injection, whose
    /// rest the near field resolves: α·merged + (1 - α)·λ̃a·previous, in one blend.
    fn record_carried_start(
        &self,
        rec: &mut Recorder,
        channels: &[usize],
        current: usize,
    ) -> GpuResult<()> {
        let alpha = self.settings.far_injection;
        self.record_blend(rec, channels, current, |c| {
            let (previous, _) = self.blend_weights(c);
            (&self.accumulation[c], (previous * (1.0 - alpha), alpha))
        })
    }

    /// One propagation step of the colour channels `channels` (one dispatch for them all) from
    /// lattice `src` into the other.
    fn record_step(
        &self,
        rec: &mut Recorder,
        channels: &[usize],
        step: usize,
        src: usize,
        (absorption, scattering): (f64, f64),
    ) -> GpuResult<()> {
        let cells = self.lattice.cell_count() as u32;
        let pipeline = self.step_pipelines.for_step(step);
        let bindings = self.step_bindings(channels, src);
        match self.settings.scheme {
            Scheme::Ilpv => {
                let keep_dc = (1.0 - absorption) as f32;
                let keep_directional = (1.0 - absorption - scattering) as f32;
                // With the clamp compensation, which applies the medium, the step only
                // transports. The first step's source is compensated by its own pass, each later
                // one's by the step before as it stores it.
                let (absorption, scattering) = if self.settings.clamp_compensation {
                    if step == 0 {
                        rec.compute(&ComputePass {
                            name: "compensate",
                            pipeline: &self.compensate_pipeline,
                            bindings: &self.compensate_bindings(channels, src),
                            push: &CompensatePush {
                                count: cells,
                                keep_dc,
                                keep_directional,
                            },
                            threads: [cells, 1, 1],
                        })?;
                    }
                    (0.0, 0.0)
                } else {
                    (absorption, scattering)
                };
                let push = IlpvPush {
                    dims: self.dims(),
                    keep: (1.0 - absorption - scattering) as f32,
                    scatter_energy: (sh::SQRT_PI_2 * scattering) as f32,
                    accumulate: u32::from(self.accumulates(step)),
                    keep_dc,
                    keep_directional,
                    compensate_result: u32::from(
                        self.settings.steps_compensate_results() && step + 1 < self.settings.steps_run(),
                    ),
                };
                rec.compute(&ComputePass {
                    name: self.propagate_pass,
                    pipeline,
                    bindings: &bindings,
                    push: &push,
                    threads: self.propagate_threads,
                })
            }
            Scheme::Lpv => {
                let push = LpvPush { dims: self.dims() };
                rec.compute(&ComputePass {
                    name: self.propagate_pass,
                    pipeline,
                    bindings: &bindings,
                    push: &push,
                    threads: self.propagate_threads,
                })
            }
        }
    }

    /// What the clamp compensation of `channels` binds: per channel (at the _R, _G, _B bindings
    /// in turn) its source `src`, written in place, and read as texels where the lattices have
    /// texel views; the neighbours' constants.
    fn compensate_bindings(&self, channels: &[usize], src: usize) -> Vec<Binding<'_>> {
        const CELLS: [u32; 3] = [
            ids::COMPENSATE_CELLS_R,
            ids::COMPENSATE_CELLS_G,
            ids::COMPENSATE_CELLS_B,
        ];
        const READS: [u32; 3] = [
            ids::COMPENSATE_READ_R,
            ids::COMPENSATE_READ_G,
            ids::COMPENSATE_READ_B,
        ];
        let mut bindings = Vec::with_capacity(2 * channels.len() + 1);
        for (i, &channel) in channels.iter().enumerate() {
            let cells = &self.lattices[channel][src];
            bindings.push(Binding::write(CELLS[i], cells));
            // Read as texels and written as storage in one pass, as the step's accumulation.
            if self.kernel.reads_texels() {
                bindings.push(Binding::texels(READS[i], cells));
            }
        }
        bindings.push(Binding::uniform(ids::COMPENSATE_NEIGHBOURS, &self.neighbours));
        bindings
    }

    /// What a step of `channels` binds: per channel (at the _R, _G, _B bindings in turn) its
    /// source `src`, its other lattice as the destination and its accumulation; the geometry
    /// and the scheme's constants. The column kernel reads its sources, the geometry and the
    /// accumulation as texels.
    fn step_bindings(&self, channels: &[usize], src: usize) -> Vec<Binding<'_>> {
        const SOURCES: [u32; 3] = [ids::STEP_SOURCE_R, ids::STEP_SOURCE_G, ids::STEP_SOURCE_B];
        const DESTINATIONS: [u32; 3] = [
            ids::STEP_DESTINATION_R,
            ids::STEP_DESTINATION_G,
            ids::STEP_DESTINATION_B,
        ];
        const ACCUMULATIONS: [u32; 3] = [
            ids::STEP_ACCUMULATION_R,
            ids::STEP_ACCUMULATION_G,
            ids::STEP_ACCUMULATION_B,
        ];
        const ACCUMULATION_READS: [u32; 3] = [
            ids::STEP_ACCUMULATION_READ_R,
            ids::STEP_ACCUMULATION_READ_G,
            ids::STEP_ACCUMULATION_READ_B,
        ];
        let texels = self.kernel.reads_texels();
        let read = |binding, buffer| match texels {
            true => Binding::texels(binding, buffer),
            false => Binding::read(binding, buffer),
        };
        let mut bindings = Vec::with_capacity(4 * channels.len() + 2);
        for (i, &channel) in channels.iter().enumerate() {
            let pair = &self.lattices[channel];
            let accumulation = &self.accumulation[channel];
            bindings.push(read(SOURCES[i], &pair[src]));
            bindings.push(Binding::write(DESTINATIONS[i], &pair[1 - src]));
            bindings.push(Binding::write(ACCUMULATIONS[i], accumulation));
            // Read as texels and written as storage in one pass (the recorder orders the
            // barriers: the read's first).
            if texels {
                bindings.push(Binding::texels(ACCUMULATION_READS[i], accumulation));
            }
        }
        bindings.push(read(ids::STEP_GEOMETRY, &self.geometry));
        let constants = match self.settings.scheme {
            Scheme::Ilpv => &self.neighbours,
            Scheme::Lpv => &self.axes,
        };
        bindings.push(Binding::uniform(ids::STEP_CONSTANTS, constants));
        bindings
    }

    /// Replace the contents of the R, G, B lattices that propagation starts from (tests and
    /// tools: propagate arbitrary lattices with [`Lpv::record_propagation`]).
    pub fn load_lattices(&mut self, gpu: &Gpu, cells: &[Vec<[f32; 4]>; 3]) -> GpuResult<()> {
        for (c, data) in cells.iter().enumerate() {
            let placed = self.cell_order.from_rows(self.lattice.dims, data, 1);
            gpu.write_buffer(&self.lattices[c][0], bytemuck::cast_slice(&placed))?;
        }
        self.result = 0;
        Ok(())
    }

    /// Replace the geometry (blocking) lattice; it must be of the settings' blocking lobe.
    pub fn load_geometry(&mut self, gpu: &Gpu, geometry: &GeometryLattice) -> anyhow::Result<()> {
        let expected = self.lattice.cell_count() * self.settings.blocking_lobe.words_per_cell();
        if geometry.lobe != self.settings.blocking_lobe || geometry.words.len() != expected {
            anyhow::bail!(
                "a {:?} geometry lattice of {} words where the method holds {:?} with {expected}",
                geometry.lobe,
                geometry.words.len(),
                self.settings.blocking_lobe
            );
        }
        let words = self.settings.blocking_lobe.words_per_cell();
        let placed = self.cell_order.from_rows(self.lattice.dims, &geometry.to_f32(), words);
        Ok(gpu.write_buffer(&self.geometry, bytemuck::cast_slice(&placed))?)
    }

    /// Propagate the loaded lattices `settings.iterations` steps (no RSM, injection or blend),
    /// holding the parts to the contract a frame holds them to (`render::part_ledger`).
    pub fn record_propagation(&mut self, rec: &mut Recorder) -> GpuResult<()> {
        let labels = self.parts();
        let mut ledger = PartLedger::default();
        let mut result = 0;
        for (index, &label) in labels.iter().enumerate() {
            let part = Part {
                index: index as u32,
                label,
            };
            let channels = self.part_channels(index)?;
            result = rec.in_part(part, |rec| {
                self.start_accumulation(rec, channels, 0)?;
                let result = self.record_steps(rec, channels, 0)?;
                for &channel in channels {
                    self.copy_to_lookup(rec, channel, result);
                }
                Ok(result)
            })?;
            ledger.add(labels, index, &rec.take_part_uses())?;
        }
        self.result = result;
        Ok(())
    }

    /// The colour channels part `part` carries.
    fn part_channels(&self, part: usize) -> GpuResult<&'static [usize]> {
        const SEPARATE: [&[usize]; 3] = [&[0], &[1], &[2]];
        const FUSED: [&[usize]; 1] = [&[0, 1, 2]];
        let parts = match self.plan {
            ChannelPlan::Separate => SEPARATE.as_slice(),
            ChannelPlan::Fused => FUSED.as_slice(),
        };
        parts.get(part).copied().ok_or_else(|| {
            GpuError::Setup(format!("the lattice has {} parts, not a part {part}", parts.len()))
        })
    }

    /// The lattices the lookup would read, per channel, in rows whatever the buffers' order.
    pub fn read_result(&self, gpu: &Gpu) -> GpuResult<[Vec<[f32; 4]>; 3]> {
        let [r, g, b] = self.result_lattices();
        let read = |buffer| self.read_rows(gpu, buffer, 1);
        Ok([read(r)?, read(g)?, read(b)?])
    }

    /// `buffer` of this lattice (`per_cell` values a cell) read back, in rows whatever the
    /// buffers' order.
    fn read_rows<T: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        buffer: &Buffer,
        per_cell: usize,
    ) -> GpuResult<Vec<T>> {
        let placed: Vec<T> = bytemuck::cast_slice(&gpu.read_buffer(buffer)?).to_vec();
        Ok(self.cell_order.to_rows(self.lattice.dims, &placed, per_cell))
    }

    /// A digest of the lattices carried to the next frame and of those the lookup reads (each
    /// read once: ILPV's final lookup reads the carried ones). Where no step writes its result
    /// (`LpvSettings::step_results_read`), the accumulation alone. The cells are hashed in
    /// rows, so that lattices in columns and in rows digest alike.
    pub fn digest(&self, gpu: &Gpu, hash: u64) -> GpuResult<u64> {
        let carried = match self.settings.step_results_read() {
            true => [0, 1, 2].map(|c| &self.lattices[c][self.result]).to_vec(),
            false => Vec::new(),
        };
        let looked_up = match self.settings.reads_final() {
            true => [].as_slice(),
            false => self.accumulation.as_slice(),
        };
        let mut hash = hash;
        for buffer in carried.into_iter().chain(looked_up) {
            let rows: Vec<[u8; 16]> = self.read_rows(gpu, buffer, 1)?;
            hash = crate::digest::fnv1a(rows.as_flattened().iter().copied(), hash);
        }
        Ok(hash)
    }

}

/// The propagation's pipelines: a frame's first step's, and the later steps' where they differ.
/// A step that blocks nothing (a frame's first, [`LpvSettings::step_blocks`]) is its own
/// pipeline (`BLOCKS`, specialisation constant 11, gi/lpv/blocking.glsl): it reads no geometry
/// and evaluates no blocking, the same bits as a blocking factor of 1, a quarter less time on
/// lavapipe (docs/performance.md).
struct StepPipelines {
    first: ComputePipeline,
    later: Option<ComputePipeline>,
}

impl StepPipelines {
    /// The pipeline of step `step` (from 0) of a frame.
    fn for_step(&self, step: usize) -> &ComputePipeline {
        match (step, &self.later) {
            (1.., Some(later)) => later,
            _ => &self.first,
        }
    }
}

/// Threads a propagation step dispatches over a lattice of `dims` cells: a thread per cell (a
/// column kernel: per piece of `column` cells of a bundle of columns), in whole workgroups of
/// `group`.
fn propagation_threads(kernel: Kernel, dims: [u32; 3], group: [u32; 3], column: u32) -> [u32; 3] {
    let threads = match kernel.column_bundle() {
        Some(bundle) => {
            let [x, y] = column_bundles(dims, bundle);
            [x, y, dims[2].div_ceil(column)]
        }
        None => dims,
    };
    [0, 1, 2].map(|i| threads[i].div_ceil(group[i]) * group[i])
}

/// The flux per colour channel the RSM sees: the punctual lights and the area-light samples.
fn emitted_flux(raster_lights: &[Light]) -> [f64; 3] {
    raster_lights.iter().fold([0.0; 3], |sum, l| {
        let c = l.color.as_dvec3() * f64::from(l.flux);
        [sum[0] + c.x, sum[1] + c.y, sum[2] + c.z]
    })
}

impl Lpv {
    /// This frame's bookkeeping before its injection; returns the number of RSM views.
    fn begin_frame(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> u32 {
        if ctx.changes.lights {
            self.frames_since_change = 0;
            self.energy = emitted_flux(ctx.raster_lights);
        }
        if ctx.changes.geometry {
            self.frames_since_change = 0;
        }
        // The RSM and the injection depend on the lights and the geometry alone.
        self.reuses_injection =
            self.injection_kept && !ctx.changes.lights && !ctx.changes.geometry;
        // Lights that move in every frame leave nothing worth keeping.
        self.injection_kept = !ctx.lights_move;
        let runs = std::mem::take(&mut self.pending_geometry);
        rec.update_buffer_runs("update geometry lattice", &self.geometry, &runs);
        // This frame's light goes into the lattice that does not hold last frame's result.
        self.current = if self.settings.scheme == Scheme::Ilpv {
            1 - self.result
        } else {
            0
        };
        self.pending_result = self.current;
        ctx.scene.shadow_view_matrices.len() as u32
    }

    /// This frame's light work, injecting from `rsm` (another lattice's, rendered this frame).
    pub(super) fn record_light_from(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        rsm: &Rsm,
    ) -> GpuResult<()> {
        let views = self.begin_frame(rec, ctx);
        self.record_inject(rec, ctx, rsm, views)
    }

    /// Whether this frame reuses the injection kept from an earlier frame (and renders no RSM):
    /// the lights and the geometry have not changed since.
    pub(super) fn reuses_injection(&self) -> bool {
        self.reuses_injection
    }

    /// Rebuild the geometry lattice's cells that geometry moving in the world boxes `regions`
    /// changes, from `scene` as it is now (see [`geometry::touched_cells`]), and queue them as
    /// runs of the buffer's order for the next frame.
    pub(super) fn follow_geometry(&mut self, scene: &Scene, regions: &[Aabb]) {
        let start = std::time::Instant::now();
        let lobe = self.settings.blocking_lobe;
        let strength = f64::from(self.settings.blocking_strength);
        let mut rebuilt = 0;
        for region in geometry::touched_cells(&self.lattice, lobe, regions) {
            let words =
                geometry::build_region(&scene.mesh, &self.lattice, &self.transfer, lobe, &region)
                    .scaled(strength)
                    .to_f32();
            self.queue_geometry_runs(&region, &words);
            rebuilt += region.count();
        }
        self.geometry_update = Some(GeometryUpdate {
            rebuilt,
            cells: self.lattice.cell_count(),
            milliseconds: start.elapsed().as_secs_f64() * 1e3,
        });
    }

    /// Queue the words of the cells of `region` (in its order) as runs of cells consecutive in
    /// the geometry buffer: one per row (or column, in [`CellOrder::Columns`]) of the region,
    /// or fewer where those span the lattice.
    fn queue_geometry_runs(&mut self, region: &CellBox, words: &[[f32; 4]]) {
        let k = self.geometry_words() as usize;
        let bytes_per_cell = (k * 16) as u64;
        for (first, cells) in self.cell_order.runs(self.lattice.dims, region) {
            let offset = self.cell_order.index(self.lattice.dims, first) as u64 * bytes_per_cell;
            let run_words: Vec<[f32; 4]> = cells
                .iter()
                .flat_map(|&local| words[local * k..][..k].iter().copied())
                .collect();
            let bytes: &[u8] = bytemuck::cast_slice(&run_words);
            match self.pending_geometry.last_mut() {
                Some((at, run)) if *at + run.len() as u64 == offset => run.extend_from_slice(bytes),
                _ => self.pending_geometry.push((offset, bytes.to_vec())),
            }
        }
    }

    /// How the GPU buffers hold the lattice's cells.
    pub fn cell_order(&self) -> CellOrder {
        self.cell_order
    }

    /// The last update of the geometry lattice after geometry moved.
    pub fn geometry_update(&self) -> Option<GeometryUpdate> {
        self.geometry_update
    }

    /// The geometry lattice the GPU holds, in rows whatever its buffer's order (tests).
    pub fn read_geometry(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 4]>> {
        let words = self.settings.blocking_lobe.words_per_cell();
        self.read_rows(gpu, &self.geometry, words)
    }

    /// The RSM this lattice renders, if it renders one.
    pub fn rsm(&self) -> Option<&Rsm> {
        self.rsm.as_ref()
    }
}

/// The name of the propagation pass (the method's core pass in the profile).
const PROPAGATE: &str = "propagate";
/// A two-scale far field's propagation, apart in the profile from the near field's core pass.
const FAR_PROPAGATE: &str = "far propagate";

impl GiMethod for Lpv {
    fn name(&self) -> &'static str {
        match self.settings.scheme {
            Scheme::Lpv => "lpv",
            Scheme::Ilpv => "ilpv",
        }
    }

    fn state_digest(&self, gpu: &Gpu) -> GpuResult<Option<u64>> {
        self.digest(gpu, crate::digest::FNV_OFFSET).map(Some)
    }

    fn record_view(&mut self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        match self.lookup.as_mut() {
            Some(lookup) => lookup.fit_view(rec.gpu(), ctx.views, view),
            None => Ok(()),
        }
    }

    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        let views = self.begin_frame(rec, ctx);
        let Some(rsm) = &self.rsm else {
            return Err(GpuError::Setup(
                "a far-field lattice injects from its near field's RSM".into(),
            ));
        };
        if views > 0 && !self.reuses_injection {
            rsm.record(rec, ctx)?;
        }
        self.record_inject(rec, ctx, rsm, views)
    }

    fn parts(&self) -> &'static [&'static str] {
        match self.plan {
            ChannelPlan::Separate => &CHANNELS,
            ChannelPlan::Fused => &ALL_CHANNELS,
        }
    }

    fn record_part(&mut self, rec: &mut Recorder, _ctx: &FrameContext, part: usize) -> GpuResult<()> {
        let channels = self.part_channels(part)?;
        self.pending_result = self.merge_and_propagate(rec, channels, self.current)?;
        for &channel in channels {
            self.copy_to_lookup(rec, channel, self.pending_result);
        }
        Ok(())
    }

    fn light_done(&mut self, _ctx: &FrameContext) {
        // This frame's light becomes "last frame's".
        self.result = self.pending_result;
        self.previous_energy = self.energy;
        self.frames += 1;
        self.frames_since_change += 1;
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        self.own_lookup()?
            .record(rec, ctx, view, &[self.lookup_field()])
    }

    fn record_lit_lookup(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        view: usize,
        direct: &DirectDraw,
    ) -> GpuResult<bool> {
        self.own_lookup()?
            .record_lit(rec, (ctx, view), direct, &[self.lookup_field()])
    }

    fn geometry_moved(
        &mut self,
        _gpu: &Gpu,
        scene: &Scene,
        regions: &[Aabb],
    ) -> anyhow::Result<Follow> {
        self.follow_geometry(scene, regions);
        Ok(Follow::Followed)
    }

    fn status(&self) -> Option<String> {
        self.geometry_update.map(|u| {
            format!(
                "geometry lattice: {} of {} cells rebuilt in {:.1} ms at the last move",
                u.rebuilt, u.cells, u.milliseconds
            )
        })
    }

    /// ILPV blends old light away by λ per frame: the weight of light from before the last
    /// change is λ^frames.
    fn convergence(&self) -> Option<Convergence> {
        (self.settings.scheme == Scheme::Ilpv).then(|| Convergence {
            measure: "weight of light from before the last change",
            remaining: f64::from(self.settings.incremental)
                .powi(self.frames_since_change.min(i32::MAX as u64) as i32),
        })
    }

    fn core_pass(&self) -> Option<CorePass> {
        // A step's ideal, by whether it blocks (a step that does not reads no geometry).
        let ideal = |blocks: bool| {
            let words = if blocks { self.geometry_words() } else { 0 };
            let writes = StepWrites {
                result: self.settings.step_results_read(),
                // ILPV's final lookup reads the last step alone: no step accumulates.
                accumulation: !self.settings.reads_final(),
            };
            UnitCost {
                bytes: cost::bytes_per_cell(self.settings.scheme, writes, words, self.plan.channels()),
                flops: cost::flops_per_cell(
                    self.settings.scheme,
                    self.settings.step_work(),
                    words,
                    self.plan.channels(),
                ),
            }
        };
        // The steps after a frame's first where it runs more than one (LPV's eight, a far
        // field's), its first otherwise (ILPV's near field).
        let typical = ideal(self.settings.step_blocks(usize::from(self.settings.steps_run() > 1)));
        let first = ideal(self.settings.step_blocks(0));
        Some(CorePass {
            pass: self.propagate_pass,
            // One channel of one cell, whether a dispatch carries one channel or three.
            unit: "cell-channel",
            units: self.lattice.cell_count() * self.plan.channels() as usize,
            cost: typical,
            first_run: (first != typical).then_some(first),
        })
    }
    fn pixel_passes(&self) -> Vec<PixelPass> {
        lookup_passes(1, self.settings.lookup_resolution)
    }

    fn describe(&self) -> Vec<String> {
        let d = self.lattice.dims;
        let [tx, ty, tz] = self.tile;
        let kernel = match (self.kernel, self.kernel.column_bundle()) {
            (Kernel::Tiled, _) => format!(
                "tiled {tx}x{ty}x{tz} (shared {} of {} bytes, z padded by {Z_PAD})",
                tile_shared_bytes(self.tile, self.geometry_words(), self.plan.channels()),
                self.device_shared_bytes
            ),
            (_, Some(bundle)) => format!(
                "{} ({} cells along z of {bundle}x{bundle} columns per thread, sources in registers and read as texels{}, workgroup {tx}x{ty})",
                self.kernel.name(),
                column_cells(d.to_array(), bundle),
                match self.kernel {
                    Kernel::SharedRows => ", each row's cells shared across the subgroup's lanes",
                    _ => "",
                }
            ),
            (_, None) => format!("naive (global memory, workgroup {tx}x{ty}x{tz})"),
        };
        let plan = match self.plan {
            ChannelPlan::Separate => "separate (a dispatch per colour channel)",
            ChannelPlan::Fused => "fused (R, G and B in one dispatch, the geometry read once)",
        };
        let mut lines = vec![
            format!(
                "{:?}: lattice {}x{}x{} cells of {:.4} (scene units), {} steps, λ_incr {}, κ {:.6}",
                self.settings.scheme,
                d.x,
                d.y,
                d.z,
                self.lattice.cell_size,
                self.settings.iterations,
                self.settings.incremental,
                self.transfer.kappa
            ),
            format!("propagation kernel: {kernel}; channels: {plan}"),
            format!("cells in buffers: {}", self.cell_order.describe()),
            format!("injection: {}", self.injection_kernel),
        ];
        if let Some(choice) = &self.autotune {
            lines.push(choice.describe());
        }
        if let Some(lookup) = &self.lookup {
            lines.push(lookup.describe());
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_writes_its_result_where_a_later_step_the_next_frame_or_the_lookup_reads_it() {
        let ilpv = |iterations, incremental, ilpv_lookup| LpvSettings {
            scheme: Scheme::Ilpv,
            iterations,
            incremental,
            ilpv_lookup,
            ..LpvSettings::default()
        };
        let (acc, last) = (IlpvLookup::Accumulated, IlpvLookup::Final);
        // A two-scale near field (λ 0, 2 steps): one step runs, its light only accumulated.
        assert_eq!(ilpv(2, 0.0, acc).steps_run(), 1);
        assert!(!ilpv(2, 0.0, acc).step_results_read());
        // A second step run reads the first one's result.
        assert_eq!(ilpv(3, 0.0, acc).steps_run(), 2);
        assert!(ilpv(3, 0.0, acc).step_results_read());
        // Carried into the next frame, or looked up alone.
        assert!(ilpv(2, 0.5, acc).step_results_read());
        assert!(ilpv(1, 0.0, last).step_results_read());
        let lpv = |iterations| LpvSettings {
            scheme: Scheme::Lpv,
            iterations,
            ..LpvSettings::default()
        };
        assert!(!lpv(1).step_results_read());
        assert!(lpv(2).step_results_read());
    }

    #[test]
    fn the_step_applies_the_medium_only_without_compensation_and_with_a_medium() {
        let ilpv = |clamp_compensation, absorption, scattering| LpvSettings {
            scheme: Scheme::Ilpv,
            clamp_compensation,
            absorption,
            scattering,
            ..LpvSettings::default()
        };
        assert!(!ilpv(true, 0.2, 0.3).step_applies_medium());
        assert!(ilpv(false, 0.2, 0.0).step_applies_medium());
        assert!(ilpv(false, 0.0, 0.3).step_applies_medium());
        assert!(!ilpv(false, 0.0, 0.0).step_applies_medium());
        // LPV's step has no medium.
        let lpv = LpvSettings {
            scheme: Scheme::Lpv,
            clamp_compensation: false,
            absorption: 0.2,
            ..LpvSettings::default()
        };
        assert!(!lpv.step_applies_medium());
    }

    #[test]
    fn column_threads_take_whole_columns_unless_the_cores_would_idle() {
        // 32x32 bundles of 2x2 columns: 16 workgroups across.
        assert_eq!(column_cells([64, 63, 64], 2), 64);
        // 4 workgroups across: each column in two halves.
        assert_eq!(column_cells([32, 32, 32], 2), 16);
        assert_eq!(column_cells([32, 31, 32], 2), 16);
        // One column a thread: 16 workgroups across, whole columns.
        assert_eq!(column_cells([32, 32, 32], 1), 32);
        // One workgroup across: 8 pieces of each column.
        assert_eq!(column_cells([16, 16, 16], 2), 2);
        assert_eq!(column_cells([9, 9, 9], 2), 2);
        assert_eq!(column_cells([8, 8, 8], 2), 1);
        assert_eq!(column_cells([2, 2, 1], 2), 1);
    }

    #[test]
    fn column_threads_cover_the_lattice_in_bundles() {
        assert_eq!(column_bundles([64, 63, 64], 2), [32, 32]);
        assert_eq!(column_bundles([64, 63, 64], 1), [64, 63]);
        let threads = |kernel: Kernel, dims| {
            let bundle = kernel.column_bundle().unwrap();
            let group = column_group(dims, bundle);
            propagation_threads(kernel, dims, group, column_cells(dims, bundle))
        };
        assert_eq!(threads(Kernel::Column, [9, 9, 9]), [8, 8, 5]);
        assert_eq!(threads(Kernel::Column, [64, 63, 64]), [32, 32, 1]);
        assert_eq!(threads(Kernel::Column, [100, 40, 20]), [64, 20, 1]);
        assert_eq!(threads(Kernel::SingleColumn, [64, 63, 64]), [64, 64, 1]);
    }

    #[test]
    fn column_workgroups_span_the_lattices_bundles_along_x_up_to_32() {
        assert_eq!(column_group([8, 8, 8], 2), [8, 8, 1]);
        assert_eq!(column_group([9, 9, 9], 2), [8, 8, 1]);
        assert_eq!(column_group([32, 32, 32], 2), [16, 4, 1]);
        assert_eq!(column_group([32, 32, 32], 1), [32, 2, 1]);
        assert_eq!(column_group([64, 63, 64], 2), [32, 2, 1]);
        assert_eq!(column_group([256, 256, 256], 2), [32, 2, 1]);
    }
}
