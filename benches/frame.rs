//! The raster frame's passes on the machine's device, timed by vkgi's own GPU profiler (the same
//! numbers `vkgi render --profile` prints, through the same frame runner): median, min and max
//! nanoseconds per pass.
//!
//! cargo bench --bench frame [-- WIDTHxHEIGHT FRAMES] [--save-baseline]   (ends with each pass
//! against benches/baselines/frame.json for this device, or stores this run there)

use vkgi::app::baseline;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::render::runner::run_frames;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let (width, height) = args
        .first()
        .map(|s| vkgi::app::cli::parse_size(s).map_err(anyhow::Error::msg))
        .transpose()?
        .unwrap_or((640, 480));
    let frames: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(20);
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = Scene::load("cornell")?;
    let mut frame = Frame::new(
        &gpu,
        &scene,
        FrameOptions {
            width,
            height,
            lights_move: true,
            ..FrameOptions::default()
        },
    )?;
    // Warm-up frames are not measured.
    let ring = run_frames(&gpu, &mut frame, None, 3, frames)?;
    println!("cornell {width}x{height}, {frames} frames");
    let report = ring.profiler.report();
    print!("{}", report.table());
    let timings = report
        .passes
        .iter()
        .chain(&report.frame)
        .map(|p| (format!("{width}x{height} {}", p.name), p.median_ns))
        .collect();
    baseline::finish("frame", &gpu.info.name, timings)
}
