//! `vkgi profile`: per-pass GPU time of LPV and ILPV per lattice size, next to the device's
//! limits and the cost-against-cells scaling. Library code, so `cargo bench` reports exactly
//! what `vkgi profile` does.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Context;
use serde::Serialize;

use crate::frame::{ChannelPlan, Frame, FrameOptions};
use crate::gi::lpv::{Lpv, LpvSettings, Scheme, cost};
use crate::gpu::Gpu;
use crate::gpu::frames::FrameRing;
use crate::gpu::profiler::summarize;
use crate::reference::ProgressBar;
use crate::scene::Scene;

use super::cli::ProfileCommandArgs;
use super::limits::{self, DeviceLimits};

/// What to profile.
#[derive(Clone, Debug)]
pub struct ProfileConfig {
    pub scene: String,
    pub methods: Vec<Scheme>,
    pub lattices: Vec<u32>,
    pub iterations: u32,
    pub warmup: u32,
    pub frames: u32,
    pub size: (u32, u32),
    pub channel_plan: ChannelPlan,
    pub tiled: bool,
}

/// One pass of one configuration.
#[derive(Clone, Debug, Serialize)]
pub struct PassRow {
    pub method: Scheme,
    pub lattice: u32,
    pub pass: String,
    pub median_ns: f64,
    pub min_ns: f64,
    pub max_ns: f64,
    /// Propagation passes: nanoseconds per cell for this step and channel.
    pub ns_per_cell_step: Option<f64>,
    /// Propagation passes: the device-limit bound's time over the measured time.
    pub fraction_of_bound: Option<f64>,
}

/// One (method, lattice) configuration.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigSummary {
    pub method: Scheme,
    pub lattice: u32,
    pub dims: [u32; 3],
    pub cells: usize,
    pub kernel: String,
    pub channel_plan: ChannelPlan,
    /// CPU time to build the geometry lattice and transfer vectors (once per scene and lattice).
    pub setup_ms: f64,
    pub frame_median_ns: f64,
    /// Median over the steps and channels of one propagation step.
    pub step_median_ns: f64,
    pub ns_per_cell_step: f64,
    pub fraction_of_bound: f64,
    /// The step's bytes and flops per cell (cost.rs) and the bound they imply.
    pub bytes_per_cell: f64,
    pub flops_per_cell: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Scaling {
    pub method: Scheme,
    /// Slope of log(step time) against log(cells); 1.0 is ideal (linear in cells).
    pub exponent: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ProfileResult {
    pub device: String,
    pub driver: String,
    pub queue_plan: String,
    pub limits: DeviceLimits,
    pub configs: Vec<ConfigSummary>,
    pub passes: Vec<PassRow>,
    pub scaling: Vec<Scaling>,
}

fn is_propagation(pass: &str) -> bool {
    pass.starts_with("propagate ")
}

/// Profile every (method, lattice) of `config`; `progress(done, total)` after each.
pub fn run(
    gpu: &Gpu,
    config: &ProfileConfig,
    mut progress: impl FnMut(u32, u32),
) -> anyhow::Result<ProfileResult> {
    let scene = Scene::load(&config.scene)?;
    let limits = limits::measure(gpu).context("measuring the device's limits")?;
    let frame = Frame::new(
        gpu,
        &scene,
        FrameOptions {
            width: config.size.0,
            height: config.size.1,
            channel_plan: config.channel_plan,
            ..FrameOptions::default()
        },
    )?;
    let total = (config.methods.len() * config.lattices.len()) as u32;
    let mut configs = Vec::new();
    let mut passes = Vec::new();
    for &method in &config.methods {
        for &lattice in &config.lattices {
            let settings = LpvSettings {
                scheme: method,
                lattice,
                iterations: config.iterations,
                tiled: config.tiled,
                ..LpvSettings::default()
            };
            let start = Instant::now();
            let mut lpv = Lpv::new(gpu, &scene, settings)?;
            let setup_ms = start.elapsed().as_secs_f64() * 1e3;
            let mut ring = FrameRing::new(gpu, gpu.queues.graphics, 2)?;
            for _ in 0..config.warmup {
                frame.submit(gpu, &mut ring, Some(&mut lpv))?;
            }
            ring.finish()?;
            ring.profiler.clear();
            for _ in 0..config.frames {
                frame.submit(gpu, &mut ring, Some(&mut lpv))?;
            }
            ring.finish()?;
            let report = ring.profiler.report();
            let cells = lpv.lattice.cell_count();
            let bytes = cost::bytes_per_cell(method, true);
            let flops = cost::flops_per_cell(method);
            let bound = limits.bound_ns(bytes * cells as f64, flops * cells as f64);
            let mut step_times = Vec::new();
            for p in &report.passes {
                let propagation = is_propagation(&p.name);
                if propagation {
                    step_times.extend(p.per_frame_ns.iter().copied());
                }
                passes.push(PassRow {
                    method,
                    lattice,
                    pass: p.name.clone(),
                    median_ns: p.median_ns,
                    min_ns: p.min_ns,
                    max_ns: p.max_ns,
                    ns_per_cell_step: propagation.then(|| p.median_ns / cells as f64),
                    fraction_of_bound: propagation.then(|| bound / p.median_ns),
                });
            }
            let frame_median_ns = report.frame.as_ref().map_or(0.0, |f| f.median_ns);
            passes.push(PassRow {
                method,
                lattice,
                pass: "frame".into(),
                median_ns: frame_median_ns,
                min_ns: report.frame.as_ref().map_or(0.0, |f| f.min_ns),
                max_ns: report.frame.as_ref().map_or(0.0, |f| f.max_ns),
                ns_per_cell_step: None,
                fraction_of_bound: None,
            });
            let step = summarize("step", step_times.len(), step_times).median_ns;
            let description = lpv_kernel_line(&lpv);
            let d = lpv.lattice.dims;
            configs.push(ConfigSummary {
                method,
                lattice,
                dims: [d.x, d.y, d.z],
                cells,
                kernel: description,
                channel_plan: frame.channel_plan(),
                setup_ms,
                frame_median_ns,
                step_median_ns: step,
                ns_per_cell_step: step / cells as f64,
                fraction_of_bound: if step > 0.0 { bound / step } else { 0.0 },
                bytes_per_cell: bytes,
                flops_per_cell: flops,
            });
            progress(configs.len() as u32, total);
        }
    }
    let scaling = config
        .methods
        .iter()
        .map(|&method| Scaling {
            method,
            exponent: fit_exponent(
                configs
                    .iter()
                    .filter(|c| c.method == method && c.step_median_ns > 0.0)
                    .map(|c| (c.cells as f64, c.step_median_ns)),
            ),
        })
        .collect();
    Ok(ProfileResult {
        device: gpu.info.name.clone(),
        driver: gpu.info.driver.clone(),
        queue_plan: gpu.queues.describe(),
        limits,
        configs,
        passes,
        scaling,
    })
}

fn lpv_kernel_line(lpv: &Lpv) -> String {
    use crate::gi::Technique;
    lpv.describe().get(1).cloned().unwrap_or_default()
}

/// Least-squares slope of ln(time) against ln(cells); NaN with fewer than two sizes.
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

impl ProfileResult {
    /// The table for humans.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "device: {} ({})", self.device, self.driver);
        let _ = writeln!(out, "queue plan: {}", self.queue_plan);
        let _ = writeln!(
            out,
            "device limits: {:.3} GB/s copy bandwidth, {:.2} GFLOP/s FMA rate",
            self.limits.bandwidth_bytes_per_ns, self.limits.flops_per_ns
        );
        for c in &self.configs {
            let _ = writeln!(
                out,
                "\n{:?} lattice {} ({}x{}x{} = {} cells), {}, channels {:?}, setup {:.0} ms (CPU)",
                c.method,
                c.lattice,
                c.dims[0],
                c.dims[1],
                c.dims[2],
                c.cells,
                c.kernel,
                c.channel_plan,
                c.setup_ms
            );
            let _ = writeln!(
                out,
                "  {:<24} {:>13} {:>13} {:>13} {:>10} {:>8}",
                "pass", "median ns", "min ns", "max ns", "ns/cell", "% bound"
            );
            for p in self
                .passes
                .iter()
                .filter(|p| p.method == c.method && p.lattice == c.lattice)
            {
                let per_cell = p
                    .ns_per_cell_step
                    .map_or(String::new(), |v| format!("{v:.2}"));
                let fraction = p
                    .fraction_of_bound
                    .map_or(String::new(), |v| format!("{:.1}%", 100.0 * v));
                let _ = writeln!(
                    out,
                    "  {:<24} {:>13.0} {:>13.0} {:>13.0} {:>10} {:>8}",
                    p.pass, p.median_ns, p.min_ns, p.max_ns, per_cell, fraction
                );
            }
            let _ = writeln!(
                out,
                "  step: {:.0} ns median, {:.2} ns per cell, {:.1}% of the device bound ({} B, {} flops per cell)",
                c.step_median_ns,
                c.ns_per_cell_step,
                100.0 * c.fraction_of_bound,
                c.bytes_per_cell,
                c.flops_per_cell
            );
        }
        for s in &self.scaling {
            let _ = writeln!(
                out,
                "\nscaling {:?}: step time ∝ cells^{:.3} (ideal 1.0)",
                s.method, s.exponent
            );
        }
        out
    }

    /// One CSV line per pass.
    pub fn csv(&self) -> String {
        let mut out = String::from(
            "method,lattice,pass,median_ns,min_ns,max_ns,ns_per_cell_step,fraction_of_bound\n",
        );
        for p in &self.passes {
            let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
            let _ = writeln!(
                out,
                "{:?},{},{},{},{},{},{},{}",
                p.method,
                p.lattice,
                p.pass,
                p.median_ns,
                p.min_ns,
                p.max_ns,
                opt(p.ns_per_cell_step),
                opt(p.fraction_of_bound)
            );
        }
        out
    }
}

/// `vkgi profile`.
pub fn run_command(args: &ProfileCommandArgs) -> anyhow::Result<()> {
    if args.frames == 0 {
        crate::bad_input!("--frames must be at least 1");
    }
    if args.lattice.is_empty() || args.method.is_empty() {
        crate::bad_input!("--method and --lattice each need at least one value");
    }
    let config = ProfileConfig {
        scene: args.scene.clone(),
        methods: args.method.clone(),
        lattices: args.lattice.clone(),
        iterations: args.iterations,
        warmup: args.warmup,
        frames: args.frames,
        size: args.size,
        channel_plan: args.channels,
        tiled: !args.naive,
    };
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let mut bar = ProgressBar::counting("profile", "configurations");
    let result = run(&gpu, &config, |done, total| bar.update(done, total))?;
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

    #[test]
    fn exponent_of_a_power_law_is_recovered() {
        let e = fit_exponent([(1e3, 2.0), (8e3, 16.0), (64e3, 128.0)].into_iter());
        assert!((e - 1.0).abs() < 1e-12);
        let e = fit_exponent([(10.0, 1.0), (100.0, 100.0)].into_iter());
        assert!((e - 2.0).abs() < 1e-12);
        assert!(fit_exponent([(10.0, 1.0)].into_iter()).is_nan());
    }
}
