//! The raster frame's passes on the machine's device, timed by vkgi's own GPU profiler (the same
//! numbers `vkgi render --profile` prints): median, min and max nanoseconds per pass.
//!
//! cargo bench --bench frame [-- WIDTHxHEIGHT FRAMES]

use vkgi::frame::{Frame, FrameOptions};
use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions};
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
    let frame = Frame::new(
        &gpu,
        &scene,
        FrameOptions {
            width,
            height,
            ..FrameOptions::default()
        },
    )?;
    let mut ring = FrameRing::new(&gpu, gpu.queues.graphics, 2)?;
    // Warm-up frames are not measured.
    for _ in 0..3 {
        ring.submit_frame(&gpu, &gpu.queues.graphics, &[], |rec| {
            frame.record(rec, None)
        })?;
    }
    ring.finish()?;
    ring.profiler.clear();
    for _ in 0..frames {
        ring.submit_frame(&gpu, &gpu.queues.graphics, &[], |rec| {
            frame.record(rec, None)
        })?;
    }
    ring.finish()?;
    println!("cornell {width}x{height}, {frames} frames");
    print!("{}", ring.profiler.report().table());
    Ok(())
}
