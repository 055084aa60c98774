//! `--kernel auto` and `--channel-plan auto`: which propagation kernel runs, and whether a dispatch
//! carries one colour channel or all three, is measured on the device, once, and kept.
//!
//! The tiled kernel (a shared-memory tile per workgroup) suits GPUs, and so does the naive one
//! (neighbours read from global memory) where a large cache holds them (an H200 from 64³ on:
//! docs/performance.md, "Item 4: the H200"); the column kernels (a
//! bundle of 2x2 columns of cells, or one column, per thread, their sources in registers and
//! read as texels) suit CPU devices such as lavapipe, where every storage-buffer load is made
//! lane by lane: the bundle reads fewer cells a column, the single column keeps fewer, the
//! shared rows (one column a thread whose lanes pass each row's cells to each other, where the
//! device allows it) read fewer without keeping more, and which is faster depends on the scheme,
//! the plan and the lattice. A candidate the device cannot run is left out. A fused dispatch of
//! the three channels reads the geometry and evaluates the blocking once; separate dispatches
//! are three parts that a device with three compute queues can overlap. All do the same
//! arithmetic per channel in the same order, and on lavapipe give the same bits (tests/lpv.rs
//! asserts it), so there the choice changes only speed. A driver that contracted the modules'
//! arithmetic differently could differ in the last bits; a CAVE whose nodes must agree bit for
//! bit can pin `--kernel` and `--channel-plan`.
//!
//! The first lattice of its kind (scheme, lattice size, geometry words, pinned settings, the
//! lookup's filter, which decides whether its cells may lie in columns) a
//! process builds on a device times a short propagation of every colour channel with each
//! candidate (kernel and plan; timed by GPU timestamps, as the profile times passes;
//! alternating, each measured run right after an unmeasured one of its own: [`SIFTING_RUNS`]
//! runs each, then the rest of [`RUNS`] for the candidates whose fastest of those came within
//! [`CONTENDING`] of the fastest candidate's, each timed by its fastest run) and takes the
//! fastest;
//! a candidate that cannot be built there
//! (no tile fits the shared memory, say) is none. The measurement records the three channels in one command buffer on one queue, so it
//! does not see separate channels overlap on a device with a compute queue each (pin
//! `--channel-plan separate` there to run them async). The choice is kept for the process and in
//! `kernels.json` in vkgi's cache folder (`$VKGI_CACHE_DIR`, else `$XDG_CACHE_HOME/vkgi`, else
//! `~/.cache/vkgi`), keyed by the device, its driver, the scheme, the lattice size (small
//! lattices favour tiles: a column kernel there has one-cell columns), the geometry words, the
//! candidates, their SPIR-V and the column kernels' shape (`column_shape`: bundle, workgroup,
//! split of a column), so later runs skip the measurement and a new build or driver measures
//! again. A cache that cannot be read or written is measured around.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use super::technique::{
    ChannelPlan, Field, Kernel, Lpv, LpvSettings, column_shape, compensate_spirv,
    shared_rows_possible,
    propagation_spirv,
};
use crate::gi::registry::Setup;
use crate::gpu::frames::FrameRing;
use crate::gpu::{Gpu, GpuResult};

/// Measured propagations of each contending candidate, each right after an unmeasured one of
/// the same candidate; the fastest counts. Every candidate runs [`SIFTING_RUNS`] times; the
/// other runs go to those whose fastest of them came within [`CONTENDING`] of the fastest
/// candidate's, so that a slower minute of the machine (which only adds time) must last
/// through all six runs of the fastest to turn the choice.
const RUNS: usize = 6;
/// Runs every candidate takes before the slow ones stop: two, so that one run slowed by the
/// machine does not drop a candidate (one run each dropped the shared rows, ILPV's fastest
/// kernel at 32³ on lavapipe, in one fresh autotune of four: 1.94 ms against 1.11-1.13).
const SIFTING_RUNS: usize = 2;
/// How much slower than the fastest candidate's sifting runs a candidate's may be for it to
/// run again.
const CONTENDING: f64 = 1.5;
/// Steps of each measured propagation.
const STEPS: u32 = 2;
/// How the cached timings were taken, in the cache's key: entries timed otherwise (per step
/// given, where a lattice records fewer; the column kernel in workgroups of 8x8 whatever the
/// lattice; runs not warmed by one of their own) are measured again.
const TIMED: &str = "ms per step recorded, column workgroups as wide as the lattice, each run warmed by one of its own, cells in columns where a CPU's kernel walks whole columns, fastest of 6 runs of the candidates within 1.5x after two";

/// A kernel and plan the autotune measured, and its time.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Timing {
    pub kernel: Kernel,
    pub plan: ChannelPlan,
    /// Milliseconds of one propagation step of all three channels.
    pub ms: f64,
}

/// The autotune's choice and what it rests on.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Choice {
    pub kernel: Kernel,
    pub plan: ChannelPlan,
    /// Every candidate that could be built, with its time.
    pub timings: Vec<Timing>,
    /// The lattice side it was measured at.
    pub lattice: u32,
    /// Where it came from this time: "measured now", "cached in PATH" or "chosen earlier in
    /// this process".
    #[serde(skip)]
    pub source: String,
}

impl Choice {
    /// One line for the profile.
    pub fn describe(&self) -> String {
        let name = |kernel: Kernel, plan: ChannelPlan| {
            let plan = format!("{plan:?}").to_lowercase();
            format!("{} {plan}", kernel.name())
        };
        let timings: Vec<String> = self
            .timings
            .iter()
            .map(|t| format!("{} {:.2} ms", name(t.kernel, t.plan), t.ms))
            .collect();
        format!(
            "chosen by the autotune: {} (one step of all channels at lattice {}: {}; {})",
            name(self.kernel, self.plan),
            self.lattice,
            timings.join(", "),
            self.source
        )
    }
}

/// The kernels and plans `settings` leave to the autotune on `gpu` (all those it can run unless
/// pinned).
fn candidates(gpu: &Gpu, settings: &LpvSettings) -> Vec<(Kernel, ChannelPlan)> {
    let kernels = match settings.kernel {
        Some(kernel) => vec![kernel],
        None => [
            Kernel::Tiled,
            Kernel::Naive,
            Kernel::Column,
            Kernel::SingleColumn,
            Kernel::SharedRows,
        ]
        .into_iter()
        .filter(|kernel| kernel.runs_on(gpu))
        .collect(),
    };
    let plans = match settings.channels {
        Some(plan) => vec![plan],
        None => vec![ChannelPlan::Separate, ChannelPlan::Fused],
    };
    kernels
        .into_iter()
        .flat_map(|k| plans.iter().map(move |&p| (k, p)))
        .collect()
}

/// The kernel and plan the autotune runs for `settings` on `setup`'s device.
pub fn choose(setup: &Setup, settings: &LpvSettings) -> anyhow::Result<Choice> {
    let key = cache_key(setup, settings);
    // One lock over look-up, measurement and write: two threads never time kernels at once (nor
    // against each other), nor write the cache file together.
    static CHOSEN: OnceLock<Mutex<HashMap<String, Choice>>> = OnceLock::new();
    let mut chosen = CHOSEN
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(choice) = chosen.get(&key) {
        return Ok(Choice {
            source: "chosen earlier in this process".into(),
            ..choice.clone()
        });
    }
    let path = cache_file();
    let cached = path
        .as_deref()
        .and_then(|p| read_cache(p).remove(&key))
        .and_then(|entry| serde_json::from_value::<Choice>(entry).ok());
    let choice = match cached {
        Some(cached) => Choice {
            source: format!("cached in {}", path.as_deref().unwrap_or(Path::new("")).display()),
            ..cached
        },
        None => {
            let measured = measure(setup, settings)?;
            if let Some(path) = &path
                && let Err(e) = write_cache(path, &key, &measured)
            {
                log::warn!("kernel autotune: not cached in {}: {e}", path.display());
            }
            measured
        }
    };
    chosen.insert(key, choice.clone());
    Ok(choice)
}

/// Time a propagation of [`probe_steps`] steps of every channel with each candidate on a lattice of
/// these settings (all candidates are built first and held together, so that their runs can
/// alternate: six lattices' memory for the measurement's length).
fn measure(setup: &Setup, settings: &LpvSettings) -> anyhow::Result<Choice> {
    let probe = |kernel, plan| {
        let settings = LpvSettings {
            kernel: Some(kernel),
            channels: Some(plan),
            iterations: probe_steps(settings),
            ..settings.clone()
        };
        Lpv::with_field(setup, settings, Field::Whole)
    };
    // A candidate that cannot be built on this device (or for this lattice) is none.
    let mut built: Vec<(Timing, Lpv)> = Vec::new();
    let mut refused = None;
    for (kernel, plan) in candidates(setup.gpu, settings) {
        match probe(kernel, plan) {
            Ok(lpv) => built.push((
                Timing {
                    kernel,
                    plan,
                    ms: f64::INFINITY,
                },
                lpv,
            )),
            Err(e) => refused = Some(e),
        }
    }
    if let (true, Some(e)) = (built.is_empty(), refused) {
        return Err(e);
    }
    let gpu = setup.gpu;
    let mut ring = FrameRing::new(gpu, 1)?;
    // Runs alternate between the candidates, so a machine that slows for a while slows all.
    // Each measured run follows an unmeasured one of the same candidate, so that it finds its
    // lattices in the caches as a frame's steps do, not evicted by the other candidates' runs
    // (which, alternating six candidates on lavapipe, ranked LPV's 32³ kernels the wrong way).
    let fastest = fastest_runs(built.len(), |candidate| {
        let lpv = &mut built[candidate].1;
        timed_propagation(gpu, &mut ring, lpv)?;
        // A lattice may record fewer steps than it is given (ILPV's last step at λ_incr 0,
        // whose light nothing reads): the time is per step recorded.
        let steps = lpv.settings.steps_run().max(1) as f64;
        Ok(timed_propagation(gpu, &mut ring, lpv)? / 1e6 / steps)
    })?;
    for ((timing, _), ms) in built.iter_mut().zip(fastest) {
        timing.ms = ms;
    }
    let timings: Vec<Timing> = built.into_iter().map(|(timing, _)| timing).collect();
    let fastest = timings
        .iter()
        .min_by(|a, b| a.ms.total_cmp(&b.ms))
        .ok_or_else(|| anyhow::anyhow!("the autotune had no propagation kernel to measure"))?;
    Ok(Choice {
        kernel: fastest.kernel,
        plan: fastest.plan,
        timings: timings.clone(),
        lattice: settings.lattice,
        source: "measured now".into(),
    })
}

/// Nanoseconds of one submitted propagation of `lpv`, timed on the GPU as the profile times the
/// passes: a submission and its wait (about 0.7 ms on an H200, 70 times a 32³ step there) would
/// otherwise decide between kernels whose steps differ by microseconds. The wall clock stands
/// in where the queue has no timestamps.
fn timed_propagation(gpu: &Gpu, ring: &mut FrameRing, lpv: &mut Lpv) -> GpuResult<f64> {
    ring.profiler.clear();
    let start = Instant::now();
    ring.submit_frame(gpu, &gpu.queues.graphics, &[], |rec| {
        lpv.record_propagation(rec)
    })?;
    ring.finish()?;
    let wall_ns = start.elapsed().as_secs_f64() * 1e9;
    let gpu_ns = ring.profiler.report().frame.map(|frame| frame.min_ns);
    Ok(gpu_ns.filter(|ns| *ns > 0.0).unwrap_or(wall_ns))
}

/// The fastest run of each of `candidates`, timed by `run` (the candidate's index to its time):
/// the candidates take turns; every one runs [`SIFTING_RUNS`] times, then those that
/// [`contends`] with the fastest of those run until each has run [`RUNS`] times.
fn fastest_runs(
    candidates: usize,
    mut run: impl FnMut(usize) -> GpuResult<f64>,
) -> GpuResult<Vec<f64>> {
    let mut fastest = vec![f64::INFINITY; candidates];
    let mut fastest_sifted = f64::INFINITY;
    for round in 0..RUNS {
        for (candidate, best) in fastest.iter_mut().enumerate() {
            if round >= SIFTING_RUNS && !contends(*best, fastest_sifted) {
                continue;
            }
            *best = best.min(run(candidate)?);
        }
        if round + 1 == SIFTING_RUNS {
            fastest_sifted = fastest.iter().copied().fold(f64::INFINITY, f64::min);
        }
    }
    Ok(fastest)
}

/// Whether a candidate whose sifting runs took `ms` at best runs again, the fastest
/// candidate's `fastest`.
fn contends(ms: f64, fastest: f64) -> bool {
    ms <= CONTENDING * fastest
}

/// The steps a candidate's probe is given: [`STEPS`], or one more or fewer where that makes its
/// step write (or leave out) its result lattice, and compensate it for a next step (or not), as
/// the lattice's own steps do, since each of those makes a different kernel
/// (`LpvSettings::step_results_read`, `LpvSettings::steps_compensate_results`).
fn probe_steps(settings: &LpvSettings) -> u32 {
    let kernel_of = |s: &LpvSettings| (s.step_results_read(), s.steps_compensate_results());
    let wanted = kernel_of(settings);
    [STEPS, STEPS + 1, STEPS - 1]
        .into_iter()
        .find(|&iterations| {
            let probe = LpvSettings {
                iterations,
                ..settings.clone()
            };
            kernel_of(&probe) == wanted
        })
        .unwrap_or(STEPS)
}

fn cache_key(setup: &Setup, settings: &LpvSettings) -> String {
    let info = &setup.gpu.info;
    let candidates = candidates(setup.gpu, settings);
    let spirv = candidates
        .iter()
        .fold(crate::digest::FNV_OFFSET, |h, &(kernel, plan)| {
            let step = propagation_spirv(settings.scheme, kernel, plan);
            let compensate = compensate_spirv(plan, kernel.reads_texels());
            crate::digest::fnv1a(step.iter().chain(compensate).copied(), h)
        });
    format!(
        "{} | {} | {:?} | shared rows possible {} | lattice {} | {} words | first step blocks {} | writes result {} | medium in step {} | compensates result {} | cell order {:?} | lookup {:?} | {candidates:?} | {spirv:016x} | {} | {TIMED}",
        info.name,
        info.driver,
        settings.scheme,
        // A device may be made without the subgroup shuffles the shared rows need.
        shared_rows_possible(setup.gpu),
        settings.lattice,
        settings.blocking_lobe.words_per_cell(),
        // Whether a frame's first step reads the geometry (its own pipeline where it does not).
        settings.step_blocks(0),
        settings.step_results_read(),
        settings.step_applies_medium(),
        settings.steps_compensate_results(),
        settings.cell_order,
        // The lookup's filter decides whether whole columns may lie in columns.
        settings.lookup_filter_on(setup.gpu),
        column_shape()
    )
}

/// vkgi's cache folder's `kernels.json`, if the environment names a folder.
fn cache_file() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    let folder = var("VKGI_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|p| p.join("vkgi")))
        .or_else(|| var("HOME").map(|p| p.join(".cache").join("vkgi")))?;
    Some(folder.join("kernels.json"))
}

/// The cache's entries, each parsed on its own where it is read: an entry another version of
/// vkgi wrote in another form is kept, not lost with the file.
fn read_cache(path: &Path) -> HashMap<String, serde_json::Value> {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default()
}

/// Add `choice` under `key`; the file is replaced whole (written beside it, then renamed), so a
/// reader never sees half of it.
fn write_cache(path: &Path, key: &str, choice: &Choice) -> std::io::Result<()> {
    let mut all = read_cache(path);
    all.insert(
        key.to_string(),
        serde_json::to_value(choice).map_err(std::io::Error::other)?,
    );
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)?;
    }
    let text = serde_json::to_string_pretty(&all).map_err(std::io::Error::other)?;
    let temporary = path.with_extension(format!("json.{}", std::process::id()));
    std::fs::write(&temporary, text)?;
    std::fs::rename(&temporary, path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gi::lpv::technique::Scheme;

    #[test]
    fn candidates_within_one_and_a_half_times_the_fastest_run_again() {
        assert!(contends(1.0, 1.0));
        assert!(contends(1.5, 1.0));
        assert!(!contends(1.51, 1.0));
        assert!(!contends(8.4, 1.4));
    }

    #[test]
    fn one_slow_run_does_not_drop_a_candidate() {
        // Candidate 1 is the fastest, but its first run is slowed past 1.5x of candidate 0's.
        let times = [vec![1.0; RUNS], vec![2.0, 0.8, 0.8, 0.8, 0.8, 0.8], vec![4.0; RUNS]];
        let mut runs = [0; 3];
        let fastest = fastest_runs(3, |candidate| {
            let time = times[candidate][runs[candidate]];
            runs[candidate] += 1;
            Ok(time)
        })
        .unwrap();
        assert_eq!(fastest, [1.0, 0.8, 4.0]);
        // The slow candidate stops after its sifting runs; the contenders run every time.
        assert_eq!(runs, [RUNS, RUNS, SIFTING_RUNS]);
    }

    #[test]
    fn the_probe_runs_the_kernel_its_lattice_runs() {
        let settings = |scheme, iterations, incremental| LpvSettings {
            scheme,
            iterations,
            incremental,
            ..LpvSettings::default()
        };
        for (scheme, iterations, incremental) in [
            (Scheme::Ilpv, 1, 0.9),
            (Scheme::Ilpv, 2, 0.0),
            (Scheme::Ilpv, 3, 0.0),
            (Scheme::Ilpv, 8, 0.9),
            (Scheme::Lpv, 1, 0.0),
            (Scheme::Lpv, 8, 0.0),
        ] {
            let lattice = settings(scheme, iterations, incremental);
            let probe = settings(scheme, probe_steps(&lattice), incremental);
            assert_eq!(
                probe.step_results_read(),
                lattice.step_results_read(),
                "{scheme:?} {iterations} {incremental}"
            );
            assert_eq!(
                probe.steps_compensate_results(),
                lattice.steps_compensate_results(),
                "{scheme:?} {iterations} {incremental}"
            );
            assert!(probe.steps_run() >= 1, "{scheme:?} {iterations} {incremental}");
        }
    }
}
