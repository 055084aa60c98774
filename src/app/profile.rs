//! `vkgi profile`: per-pass GPU time of every registered GI method over its size axis (e.g.
//! lattice cells), with its core pass next to the device's limits and the cost-against-size
//! scaling. Library code, so `cargo bench` reports exactly what `vkgi profile` does.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Context;
use serde::Serialize;

use crate::error::InputError;
use crate::gi::registry::{self, MethodEntry, Setup};
use crate::gi::settings::Settings;
use crate::gi::{CorePass, PixelPass, UnitCost};
use crate::gpu::profiler::summarize;
use crate::gpu::{Gpu, PassTiming, ProfileReport, ScopeTag, Stage};
use crate::render::passes::{DIRECT_LIGHTING, MaterialTerms};
use crate::render::runner::run_frames;
use crate::render::{Frame, FrameOptions, SubmitPlan, cost};
use crate::scene::Scene;

use super::cli::ProfileCommandArgs;
use super::limits::{self, DeviceLimits};

/// What to profile.
#[derive(Clone, Debug)]
pub struct ProfileConfig {
    pub scene: String,
    /// Registered method names (empty: every registered method).
    pub methods: Vec<String>,
    /// Setting values: a list for a method's size axis, one value for anything else.
    pub grid: Vec<(String, Vec<String>)>,
    pub warmup: u32,
    pub frames: u32,
    pub size: (u32, u32),
    pub submit: SubmitPlan,
    /// Draw the methods' lookups apart from direct lighting (`FrameOptions::lookup_apart`).
    pub lookup_apart: bool,
}

/// One pass of one configuration.
#[derive(Clone, Debug, Serialize)]
pub struct PassRow {
    pub method: &'static str,
    /// The swept setting and its value in this configuration (e.g. lattice, 16).
    pub axis: Option<&'static str>,
    pub value: Option<String>,
    pub pass: String,
    pub stage: Stage,
    pub median_ns: f64,
    pub min_ns: f64,
    pub max_ns: f64,
    /// Runs of the method's core pass: nanoseconds per unit of work (e.g. per cell).
    pub ns_per_unit: Option<f64>,
    /// Runs of the core pass: the device-limit bound's time over the measured time.
    pub fraction_of_bound: Option<f64>,
}

/// The core pass of one configuration, against the device's bounds.
#[derive(Clone, Debug, Serialize)]
pub struct CoreSummary {
    pub pass: &'static str,
    pub unit: &'static str,
    pub units: usize,
    /// Median over the runs of one core pass.
    pub median_ns: f64,
    pub ns_per_unit: f64,
    pub fraction_of_bound: f64,
    pub bytes_per_unit: f64,
    pub flops_per_unit: f64,
    /// Where a frame's first run must do less (a propagation's first step, which blocks
    /// nothing), what it must do: its row is held to that bound and left out of the median.
    pub first_run: Option<UnitCost>,
    /// A per-pixel pass whose pixels without a surface need less: how many pixels a surface
    /// covers, and the bytes each other one is held to (no flops).
    pub background: Option<Background>,
}

/// The pixels of a view a surface covers, and what a per-pixel pass is held to at the others.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Background {
    pub covered_pixels: usize,
    pub bytes_per_pixel: f64,
}

/// One (method, axis value) configuration.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigSummary {
    pub method: &'static str,
    pub axis: Option<&'static str>,
    pub value: Option<String>,
    /// How the method ran (its own description).
    pub description: Vec<String>,
    pub submit_plan: SubmitPlan,
    /// CPU time to build the method (e.g. transfer vectors and geometry lattice).
    pub setup_ms: f64,
    /// The device's limits probed just before and just after this configuration's frames
    /// (the better of the two), which its bounds are stated against: on a shared machine
    /// the device's speed drifts over a long profile.
    pub limits: DeviceLimits,
    pub frame_median_ns: f64,
    pub core: Option<CoreSummary>,
    /// The frame's and the method's per-pixel passes against the device's bounds (unit
    /// "pixel", units the view's pixels).
    pub pixel_passes: Vec<CoreSummary>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Scaling {
    pub method: &'static str,
    /// Slope of log(core pass time) against log(units); 1.0 is ideal (linear in size). NaN
    /// with fewer than two sizes.
    pub exponent: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ProfileResult {
    /// The scene's statistics line (triangles, emitters, lights, bounds).
    pub scene: String,
    pub device: String,
    pub driver: String,
    pub queue_plan: String,
    /// How the frame's direct lighting runs (src/render/passes.rs).
    pub direct_lighting: String,
    /// How the frame's tone mapping runs (src/render/passes.rs).
    pub tone_map: String,
    /// The best limits probed over the whole run (each configuration's bounds use its own).
    pub limits: DeviceLimits,
    pub configs: Vec<ConfigSummary>,
    pub passes: Vec<PassRow>,
    pub scaling: Vec<Scaling>,
}

/// The methods of `names` (every registered one when empty).
pub fn entries(names: &[String]) -> Result<Vec<&'static MethodEntry>, InputError> {
    if names.is_empty() {
        return Ok(registry::methods().collect());
    }
    let mut entries = Vec::new();
    for name in names {
        if let Some(entry) = registry::lookup(name)?
            && !entries.iter().any(|e: &&MethodEntry| e.name == entry.name)
        {
            entries.push(entry);
        }
    }
    Ok(entries)
}

/// The settings of each configuration of `entry`: one per value of its size axis.
fn configurations(
    entry: &'static MethodEntry,
    grid: &[(String, Vec<String>)],
) -> Result<Vec<(Option<String>, Settings)>, InputError> {
    let axis = entry.profile_axis;
    let mut singles = Vec::new();
    for (name, values) in grid {
        let declared = entry.settings.iter().any(|s| s.name == name);
        if Some(name.as_str()) == axis || !declared {
            continue;
        }
        if values.len() > 1 {
            return Err(InputError::new(format!(
                "--{name}: vkgi profile sweeps only a method's size axis; give one value"
            )));
        }
        singles.extend(values.first().map(|v| (name.clone(), v.clone())));
    }
    let base = entry.settings(&singles)?;
    let Some(axis) = axis else {
        return Ok(vec![(None, base)]);
    };
    let given = grid.iter().find(|(n, _)| n == axis).map(|(_, v)| v.clone());
    let values: Vec<String> = match given {
        Some(values) => values,
        None => {
            let sweep = entry
                .settings
                .iter()
                .find(|s| s.name == axis)
                .map_or(&[][..], |s| s.sweep);
            sweep.iter().map(|v| v.to_string()).collect()
        }
    };
    values
        .into_iter()
        .map(|value| {
            let mut settings = base.clone();
            settings
                .set(axis, &value)
                .map_err(|e| InputError::new(format!("{} (method {})", e.0, entry.name)))?;
            Ok((Some(value), settings))
        })
        .collect()
}

/// Profile every configuration of `config`; `progress(done, total)` after each.
pub fn run(
    gpu: &Gpu,
    config: &ProfileConfig,
    mut progress: impl FnMut(u32, u32),
) -> anyhow::Result<ProfileResult> {
    let scene = Scene::load(&config.scene)?;
    let statistics = scene.statistics();
    let lights = scene.raster_lights().len() as u32;
    let mut plan = Vec::new();
    for entry in entries(&config.methods)? {
        for (value, settings) in configurations(entry, &config.grid)? {
            plan.push((entry, value, settings));
        }
    }
    let probe = || limits::measure(gpu).context("measuring the device's limits");
    let mut run_limits: Option<DeviceLimits> = None;
    let mut frame = Frame::new(
        gpu,
        &scene,
        FrameOptions {
            width: config.size.0,
            height: config.size.1,
            submit: config.submit,
            lights_move: true,
            lookup_apart: config.lookup_apart,
            ..FrameOptions::default()
        },
    )?;
    let total = plan.len() as u32;
    let mut configs = Vec::new();
    let mut passes = Vec::new();
    for (entry, value, settings) in plan {
        let start = Instant::now();
        let mut method = entry.create(&Setup::new(gpu, &scene), &settings)?;
        let setup_ms = start.elapsed().as_secs_f64() * 1e3;
        let before = probe()?;
        let ring = run_frames(
            gpu,
            &mut frame,
            Some(method.as_mut()),
            config.warmup,
            config.frames,
        )?;
        let limits = before.best(probe()?);
        run_limits = Some(run_limits.map_or(limits, |run| run.best(limits)));
        let report = ring.profiler.report();
        let core = method.core_pass();
        let bound_of = |c: &CorePass, cost: UnitCost| {
            let units = c.units as f64;
            limits.bound_ns(cost.bytes * units, cost.flops * units)
        };
        let bound = core.as_ref().map(|c| bound_of(c, c.cost));
        let timings = report.passes.iter().chain(report.frame.as_ref());
        for p in timings {
            let is_core = core
                .as_ref()
                .is_some_and(|c| p.tag.method == Some(entry.name) && p.tag.pass == c.pass);
            // A frame's first run held to its own ideal where that differs.
            let bound = match core.as_ref().and_then(|c| c.first_run.map(|f| (c, f))) {
                Some((c, first)) if is_first_run(c, &p.tag) => Some(bound_of(c, first)),
                _ => bound,
            };
            passes.push(PassRow {
                method: entry.name,
                axis: entry.profile_axis,
                value: value.clone(),
                pass: p.name.clone(),
                stage: p.tag.stage,
                median_ns: p.median_ns,
                min_ns: p.min_ns,
                max_ns: p.max_ns,
                ns_per_unit: core
                    .as_ref()
                    .filter(|_| is_core)
                    .map(|c| p.median_ns / c.units as f64),
                fraction_of_bound: bound.filter(|_| is_core).map(|b| b / p.median_ns),
            });
        }
        let core = core.map(|c| {
            let median = core_pass_median(&report, entry.name, &c);
            let units = c.units.max(1) as f64;
            CoreSummary {
                pass: c.pass,
                unit: c.unit,
                units: c.units,
                median_ns: median,
                ns_per_unit: median / units,
                fraction_of_bound: match bound {
                    Some(b) if median > 0.0 => b / median,
                    _ => 0.0,
                },
                bytes_per_unit: c.cost.bytes,
                flops_per_unit: c.cost.flops,
                first_run: c.first_run,
                background: None,
            }
        });
        let pixels = config.size.0 as usize * config.size.1 as usize;
        let covered = frame
            .read_positions(gpu)?
            .iter()
            .filter(|p| p[3] != 0.0)
            .count();
        let frame_passes = cost::pixel_passes(lights, MaterialTerms::of(&scene));
        let direct = frame_passes.iter().find(|p| p.pass == DIRECT_LIGHTING);
        // The passes that ran (direct lighting and the lookup run as one pass or apart).
        let pixel_passes = frame_passes
            .iter()
            .cloned()
            .map(|p| (None, p))
            .chain(
                method
                    .pixel_passes()
                    .into_iter()
                    .map(|p| (Some(entry.name), with_direct_lighting(p, direct))),
            )
            .filter(|(owner, p)| ran(&report, *owner, p.pass))
            .map(|(owner, p)| pixel_summary(&report, &limits, owner, &p, (pixels, covered)))
            .collect();
        configs.push(ConfigSummary {
            method: entry.name,
            axis: entry.profile_axis,
            value,
            description: method.describe(),
            submit_plan: frame.submit_plan(),
            setup_ms,
            limits,
            frame_median_ns: report.frame.as_ref().map_or(0.0, |f| f.median_ns),
            core,
            pixel_passes,
        });
        progress(configs.len() as u32, total);
    }
    let mut scaling: Vec<Scaling> = Vec::new();
    for c in &configs {
        if c.core.is_none() || scaling.iter().any(|s| s.method == c.method) {
            continue;
        }
        let points = configs
            .iter()
            .filter(|o| o.method == c.method)
            .filter_map(|o| o.core.as_ref())
            .filter(|k| k.median_ns > 0.0)
            .map(|k| (k.units as f64, k.median_ns));
        scaling.push(Scaling {
            method: c.method,
            exponent: fit_exponent(points),
        });
    }
    Ok(ProfileResult {
        scene: statistics,
        device: gpu.info.name.clone(),
        driver: gpu.info.driver.clone(),
        queue_plan: gpu.queues.describe(),
        direct_lighting: frame.direct_lighting(),
        tone_map: frame.tone_map(),
        limits: match run_limits {
            Some(limits) => limits,
            None => probe()?,
        },
        configs,
        passes,
        scaling,
    })
}

/// The median time of one run of `method`'s core pass `core` in `report`, a frame's first run
/// left out where it is held to an ideal of its own (0 if it never ran).
pub fn core_pass_median(report: &ProfileReport, method: &str, core: &CorePass) -> f64 {
    median_of(
        report
            .passes
            .iter()
            .filter(|p| p.tag.method == Some(method) && p.tag.pass == core.pass)
            .filter(|p| core.first_run.is_none() || !is_first_run(core, &p.tag)),
    )
}

/// Whether the pass tagged `tag` is a frame's first run of `core` (its first step).
fn is_first_run(core: &CorePass, tag: &ScopeTag) -> bool {
    tag.pass == core.pass && tag.step == Some(1)
}

/// The median time of one run of pass `pass` of `owner` (None: the frame) in `report` (0 if
/// it never ran).
fn pass_median(report: &ProfileReport, owner: Option<&str>, pass: &str) -> f64 {
    median_of(
        report
            .passes
            .iter()
            .filter(|p| p.tag.method == owner && p.tag.pass == pass),
    )
}

/// The median of every per-frame time of `passes` (0 if there is none).
fn median_of<'a>(passes: impl Iterator<Item = &'a PassTiming>) -> f64 {
    let times: Vec<f64> = passes
        .flat_map(|p| p.per_frame_ns.iter().copied())
        .collect();
    summarize("core", times.len(), times).median_ns
}

/// Whether pass `pass` of `owner` (None: the frame) ran in the profiled frames.
fn ran(report: &ProfileReport, owner: Option<&str>, pass: &str) -> bool {
    report
        .passes
        .iter()
        .any(|p| p.tag.method == owner && p.tag.pass == pass)
}

/// A method's per-pixel pass with the bytes and flops of the frame's direct lighting (`direct`)
/// added where it draws direct lighting too.
fn with_direct_lighting(pass: PixelPass, direct: Option<&PixelPass>) -> PixelPass {
    match direct {
        Some(direct) if pass.with_direct_lighting => PixelPass {
            bytes_per_pixel: pass.bytes_per_pixel + direct.bytes_per_pixel,
            flops_per_pixel: pass.flops_per_pixel + direct.flops_per_pixel,
            background_bytes: pass
                .background_bytes
                .zip(direct.background_bytes)
                .map(|(own, direct)| own + direct),
            ..pass
        },
        _ => pass,
    }
}

/// Per-pixel pass `pass` of `owner` (None: the frame) over `pixels` pixels, `covered` of
/// them by a surface, against the bound.
fn pixel_summary(
    report: &ProfileReport,
    limits: &DeviceLimits,
    owner: Option<&str>,
    pass: &PixelPass,
    (pixels, covered): (usize, usize),
) -> CoreSummary {
    let median = pass_median(report, owner, pass.pass);
    let units = pixels.max(1) as f64;
    let (bytes, flops) = pass.ideal(pixels, covered);
    let bound = limits.bound_ns(bytes, flops);
    CoreSummary {
        pass: pass.pass,
        unit: "pixel",
        units: pixels,
        median_ns: median,
        ns_per_unit: median / units,
        fraction_of_bound: if median > 0.0 { bound / median } else { 0.0 },
        bytes_per_unit: pass.bytes_per_pixel,
        flops_per_unit: pass.flops_per_pixel,
        first_run: None,
        background: pass.background_bytes.map(|bytes_per_pixel| Background {
            covered_pixels: covered.min(pixels),
            bytes_per_pixel,
        }),
    }
}

/// Least-squares slope of ln(time) against ln(units); NaN with fewer than two sizes.
pub fn fit_exponent(points: impl Iterator<Item = (f64, f64)>) -> f64 {
    let p: Vec<(f64, f64)> = points.map(|(x, y)| (x.ln(), y.ln())).collect();
    if p.len() < 2 {
        return f64::NAN;
    }
    let n = p.len() as f64;
    let (mx, my) = p
        .iter()
        .fold((0.0, 0.0), |a, q| (a.0 + q.0 / n, a.1 + q.1 / n));
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    if sxx == 0.0 {
        return f64::NAN;
    }
    p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum::<f64>() / sxx
}

impl ConfigSummary {
    /// "METHOD AXIS VALUE" (e.g. a lattice size), or the method alone.
    pub fn label(&self) -> String {
        match (self.axis, &self.value) {
            (Some(axis), Some(value)) => format!("{} {axis} {value}", self.method),
            _ => self.method.to_string(),
        }
    }
}

impl ProfileResult {
    /// The table for humans.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "{}", self.scene);
        let _ = writeln!(out, "device: {} ({})", self.device, self.driver);
        let _ = writeln!(out, "queue plan: {}", self.queue_plan);
        let _ = writeln!(out, "direct lighting: {}", self.direct_lighting);
        let _ = writeln!(out, "tone map: {}", self.tone_map);
        let _ = writeln!(
            out,
            "device limits, the best of the run: {:.3} GB/s copy bandwidth, {:.2} GFLOP/s FMA rate",
            self.limits.bandwidth_bytes_per_ns, self.limits.flops_per_ns
        );
        for c in &self.configs {
            let _ = writeln!(
                out,
                "\n{}: parts {:?}, set-up {:.0} ms (CPU)",
                c.label(),
                c.submit_plan,
                c.setup_ms
            );
            for line in &c.description {
                let _ = writeln!(out, "  {line}");
            }
            let _ = writeln!(
                out,
                "  device limits around its frames (the bounds below): {:.3} GB/s, {:.2} GFLOP/s",
                c.limits.bandwidth_bytes_per_ns, c.limits.flops_per_ns
            );
            let unit = c.core.as_ref().map_or("unit", |k| k.unit);
            let _ = writeln!(
                out,
                "  {:<24} {:>13} {:>13} {:>13} {:>10} {:>8}",
                "pass",
                "median ns",
                "min ns",
                "max ns",
                format!("ns/{unit}"),
                "% bound"
            );
            for p in self
                .passes
                .iter()
                .filter(|p| p.method == c.method && p.value == c.value)
            {
                let per_unit = p.ns_per_unit.map_or(String::new(), |v| format!("{v:.2}"));
                let fraction = p
                    .fraction_of_bound
                    .map_or(String::new(), |v| format!("{:.1}%", 100.0 * v));
                let _ = writeln!(
                    out,
                    "  {:<24} {:>13.0} {:>13.0} {:>13.0} {:>10} {:>8}",
                    p.pass, p.median_ns, p.min_ns, p.max_ns, per_unit, fraction
                );
            }
            for k in c.core.iter().chain(&c.pixel_passes) {
                let _ = writeln!(
                    out,
                    "  {}: {:.0} ns median over {} {}s, {:.2} ns per {}, {:.1}% of the device bound ({:.1} B, {:.0} flops per {})",
                    k.pass,
                    k.median_ns,
                    k.units,
                    k.unit,
                    k.ns_per_unit,
                    k.unit,
                    100.0 * k.fraction_of_bound,
                    k.bytes_per_unit,
                    k.flops_per_unit,
                    k.unit
                );
                if let Some(b) = k.background {
                    let _ = writeln!(
                        out,
                        "    of them {} covered by a surface, held to that; the other {} to {:.1} B and no flops each",
                        b.covered_pixels,
                        k.units - b.covered_pixels,
                        b.bytes_per_pixel
                    );
                }
                if let Some(first) = k.first_run {
                    let _ = writeln!(
                        out,
                        "    {} step 1 held to its own bound and left out of the median: a frame's first step blocks nothing ({:.1} B, {:.0} flops per {})",
                        k.pass, first.bytes, first.flops, k.unit
                    );
                }
            }
        }
        for s in &self.scaling {
            let unit = self
                .configs
                .iter()
                .find(|c| c.method == s.method)
                .and_then(|c| c.core.as_ref())
                .map_or("unit", |k| k.unit);
            if s.exponent.is_finite() {
                let _ = writeln!(
                    out,
                    "\nscaling {}: core pass time ∝ {unit}s^{:.3} (ideal 1.0)",
                    s.method, s.exponent
                );
            } else {
                let _ = writeln!(
                    out,
                    "\nscaling {}: not fitted (it needs two sizes or more)",
                    s.method
                );
            }
        }
        out
    }

    /// One CSV line per pass.
    pub fn csv(&self) -> String {
        let mut out = String::from(
            "method,axis,value,pass,stage,median_ns,min_ns,max_ns,ns_per_unit,fraction_of_bound\n",
        );
        for p in &self.passes {
            let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
            let _ = writeln!(
                out,
                "{},{},{},{},{:?},{},{},{},{},{}",
                p.method,
                p.axis.unwrap_or(""),
                p.value.as_deref().unwrap_or(""),
                p.pass,
                p.stage,
                p.median_ns,
                p.min_ns,
                p.max_ns,
                opt(p.ns_per_unit),
                opt(p.fraction_of_bound)
            );
        }
        out
    }
}

/// `vkgi profile`.
pub fn run_command(args: &ProfileCommandArgs) -> anyhow::Result<()> {
    let config = ProfileConfig {
        scene: args.scene.clone(),
        methods: args.method.clone(),
        grid: args.grid.values.clone(),
        warmup: args.warmup,
        frames: args.frames,
        size: args.size,
        submit: args.parts,
        lookup_apart: args.lookup_apart,
    };
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let bar = super::progress::counting("profile", "configurations");
    let result = run(&gpu, &config, |done, total| {
        super::progress::update(&bar, done, total)
    })?;
    super::render::check_validation(&gpu)?;
    print!("{}", result.table());
    if let Some(path) = &args.json {
        crate::imageio::write_text(path, &serde_json::to_string_pretty(&result)?)?;
    }
    if let Some(path) = &args.csv {
        crate::imageio::write_text(path, &result.csv())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A profile of `method`'s "propagate" whose step `s` (from 1) took `per_step[s - 1]` ns
    /// in each of three frames.
    fn steps_report(method: &'static str, per_step: &[f64]) -> ProfileReport {
        let passes = per_step
            .iter()
            .enumerate()
            .map(|(s, &ns)| PassTiming {
                name: format!("propagate step {}", s + 1),
                tag: ScopeTag {
                    method: Some(method),
                    stage: Stage::GiPart,
                    pass: "propagate",
                    step: Some(s as u32 + 1),
                    ..ScopeTag::default()
                },
                samples: 3,
                per_frame_ns: vec![ns; 3],
                avg_ns: ns,
                median_ns: ns,
                min_ns: ns,
                max_ns: ns,
                percent_of_frame: 0.0,
            })
            .collect();
        ProfileReport {
            device: String::new(),
            frames: 3,
            dropped_scopes: 0,
            passes,
            frame: None,
            notes: Vec::new(),
        }
    }

    #[test]
    fn the_core_median_leaves_the_first_step_out_where_it_does_less() {
        let cost = UnitCost {
            bytes: 64.0,
            flops: 500.0,
        };
        let core = |first_run| CorePass {
            pass: "propagate",
            unit: "cell-channel",
            units: 1,
            cost,
            first_run,
        };
        // A first step far faster than the rest, then four steps of 10 and 20 ns.
        let report = steps_report("lpv", &[1.0, 10.0, 10.0, 20.0, 20.0]);
        let lighter = Some(UnitCost {
            bytes: 48.0,
            ..cost
        });
        // Without step 1: the median of 12 samples, six of 10 and six of 20.
        assert_eq!(core_pass_median(&report, "lpv", &core(lighter)), 15.0);
        // With it: fifteen samples, the eighth of them 10.
        assert_eq!(core_pass_median(&report, "lpv", &core(None)), 10.0);
        // Another method's passes are not this one's.
        assert_eq!(core_pass_median(&report, "ilpv", &core(None)), 0.0);
    }

    #[test]
    fn exponent_of_a_power_law_is_recovered() {
        let e = fit_exponent([(1e3, 2.0), (8e3, 16.0), (64e3, 128.0)].into_iter());
        assert!((e - 1.0).abs() < 1e-12);
        let e = fit_exponent([(10.0, 1.0), (100.0, 100.0)].into_iter());
        assert!((e - 2.0).abs() < 1e-12);
        assert!(fit_exponent([(10.0, 1.0)].into_iter()).is_nan());
    }

    #[test]
    fn only_the_size_axis_takes_a_list() {
        let Some(entry) = registry::methods().find(|m| m.profile_axis.is_some()) else {
            return;
        };
        let Some(axis) = entry.profile_axis else {
            return;
        };
        let grid = vec![(axis.to_string(), vec!["4".to_string(), "8".to_string()])];
        let configs = match configurations(entry, &grid) {
            Ok(c) => c,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(configs.len(), 2);
        let other = entry
            .settings
            .iter()
            .find(|s| s.name != axis && !s.sweep.is_empty());
        if let Some(other) = other {
            let grid = vec![(
                other.name.to_string(),
                other.sweep.iter().map(|v| v.to_string()).collect(),
            )];
            assert!(configurations(entry, &grid).is_err());
        }
    }
}
