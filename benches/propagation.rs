//! Every method with a size axis (LPV and ILPV: the lattice) per size: the tiled, naive, column
//! single-column and (where the device allows them, else skipped) shared-rows kernels, a dispatch per colour channel against the three fused in one,
//! and one submission against one per part (colour channel) on its queue, timed by vkgi's own
//! GPU profiler through the same code as `vkgi profile` (so both print the same numbers).
//!
//! cargo bench --bench propagation [-- SIZES FRAMES] [--save-baseline], e.g. `-- 8,16,32,64 10`
//! (ends with each number against benches/baselines/propagation.json for this device, or stores
//! this run there with --save-baseline)

use vkgi::app::baseline;
use vkgi::app::profile::{ProfileConfig, run};
use vkgi::gi::registry;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::render::SubmitPlan;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let sizes: Vec<String> = match args.first() {
        Some(list) => list.split(',').map(str::to_string).collect(),
        None => vec!["8".into(), "16".into(), "32".into()],
    };
    let frames: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(5);
    let gpu = Gpu::new(&GpuOptions::default())?;
    let methods: Vec<&registry::MethodEntry> = registry::methods()
        .filter(|m| m.profile_axis.is_some())
        .collect();
    let variants = [
        (
            "tiled, sequential parts",
            "tiled",
            "separate",
            SubmitPlan::Sequential,
        ),
        (
            "naive, sequential parts",
            "naive",
            "separate",
            SubmitPlan::Sequential,
        ),
        (
            "column, sequential parts",
            "column",
            "separate",
            SubmitPlan::Sequential,
        ),
        (
            "tiled, one queue per part",
            "tiled",
            "separate",
            SubmitPlan::Async,
        ),
        (
            "tiled, channels fused",
            "tiled",
            "fused",
            SubmitPlan::Sequential,
        ),
        (
            "column, channels fused",
            "column",
            "fused",
            SubmitPlan::Sequential,
        ),
        (
            "single column, sequential parts",
            "single-column",
            "separate",
            SubmitPlan::Sequential,
        ),
        (
            "single column, channels fused",
            "single-column",
            "fused",
            SubmitPlan::Sequential,
        ),
        (
            "shared rows, channels fused",
            "shared-rows",
            "fused",
            SubmitPlan::Sequential,
        ),
    ];
    let mut summary = Vec::new();
    for (name, kernel, channels, plan) in variants {
        for method in &methods {
            let Some(axis) = method.profile_axis else {
                continue;
            };
            let grid = vec![
                (axis.to_string(), sizes.clone()),
                ("iterations".to_string(), vec!["8".to_string()]),
                ("kernel".to_string(), vec![kernel.to_string()]),
                ("channel-plan".to_string(), vec![channels.to_string()]),
            ];
            let config = ProfileConfig {
                scene: "cornell".into(),
                methods: vec![method.name.to_string()],
                grid,
                warmup: 1,
                frames,
                size: (160, 120),
                submit: plan,
                lookup_apart: false,
            };
            // The shared rows run where the device's subgroups lie along x (a CPU device with
            // shuffles, workgroups a whole number of subgroups wide): elsewhere skipped.
            let result = match run(&gpu, &config, |_, _| {}) {
                Err(e) if kernel == "shared-rows" => {
                    println!("==== {name}: {}: skipped ({e:#}) ====", method.name);
                    continue;
                }
                result => result?,
            };
            println!("==== {name}: {} ====", method.name);
            print!("{}", result.table());
            for c in &result.configs {
                summary.push((
                    name,
                    c.label(),
                    c.core.as_ref().map_or(0.0, |k| k.ns_per_unit),
                    c.frame_median_ns,
                ));
            }
        }
    }
    println!(
        "\n==== summary: median ns of the core pass per unit (cell and channel) and per frame ===="
    );
    let mut timings = baseline::Timings::new();
    for (name, label, core, frame) in summary {
        println!("{name:<28} {label:<20}: core {core:>9.2} ns per unit, frame {frame:>13.0} ns");
        timings.insert(format!("{name}, {label}, core pass per unit"), core);
        timings.insert(format!("{name}, {label}, frame"), frame);
    }
    baseline::finish("propagation", &gpu.info.name, timings)
}
