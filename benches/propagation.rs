//! LPV and ILPV propagation per lattice size, tiled against naive and one submission against
//! one per colour-channel queue, timed by vkgi's own GPU profiler through the same code as
//! `vkgi profile` (so both print the same numbers).
//!
//! cargo bench --bench propagation [-- LATTICES FRAMES], e.g. `-- 8,16,32,64 10`

use vkgi::app::profile::{ProfileConfig, run};
use vkgi::frame::ChannelPlan;
use vkgi::gi::lpv::Scheme;
use vkgi::gpu::{Gpu, GpuOptions};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let lattices: Vec<u32> = match args.first() {
        Some(list) => list.split(',').map(str::parse).collect::<Result<_, _>>()?,
        None => vec![8, 16, 32],
    };
    let frames: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(5);
    let gpu = Gpu::new(&GpuOptions::default())?;
    let variants = [
        ("tiled, sequential channels", true, ChannelPlan::Sequential),
        ("naive, sequential channels", false, ChannelPlan::Sequential),
        ("tiled, one queue per channel", true, ChannelPlan::Async),
    ];
    let mut summary = Vec::new();
    for (name, tiled, plan) in variants {
        let config = ProfileConfig {
            scene: "cornell".into(),
            methods: vec![Scheme::Lpv, Scheme::Ilpv],
            lattices: lattices.clone(),
            iterations: 8,
            warmup: 1,
            frames,
            size: (160, 120),
            channel_plan: plan,
            tiled,
        };
        let result = run(&gpu, &config, |_, _| {})?;
        println!("==== {name} ====");
        print!("{}", result.table());
        for c in &result.configs {
            summary.push((
                name,
                c.method,
                c.lattice,
                c.step_median_ns,
                c.frame_median_ns,
            ));
        }
    }
    println!("\n==== summary: median ns per propagation step (per channel) and per frame ====");
    for (name, method, lattice, step, frame) in summary {
        println!(
            "{name:<30} {method:?} lattice {lattice:>4}: step {step:>13.0} ns, frame {frame:>13.0} ns"
        );
    }
    Ok(())
}
