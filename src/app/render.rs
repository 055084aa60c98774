//! `vkgi render`: a headless render of a scene, with or without GI, optionally profiled.

use anyhow::Context;

use crate::frame::Frame;
use crate::gi::Technique;
use crate::gi::lpv::Lpv;
use crate::gpu::Gpu;
use crate::gpu::frames::FrameRing;
use crate::imageio::HdrImage;
use crate::scene::Scene;

use super::cli::{Method, RenderArgs};
use super::output;

/// Frames rendered for ILPV (whose light builds up over frames) or when profiling, when
/// `--frames` is not given.
const DEFAULT_MANY_FRAMES: u32 = 16;
/// Frames in flight in the frame ring.
const FRAMES_IN_FLIGHT: usize = 2;

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene)?;
    let frames = match args.frames {
        Some(0) => crate::bad_input!("--frames must be at least 1"),
        Some(n) => n,
        None if args.profile.wanted() || args.gi.method == Method::Ilpv => DEFAULT_MANY_FRAMES,
        None => 1,
    };
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let frame = Frame::new(&gpu, &scene, args.frame.options())?;
    let mut technique: Option<Box<dyn Technique>> = match args.gi.lpv_settings() {
        Some(settings) => Some(Box::new(Lpv::new(&gpu, &scene, settings)?)),
        None => None,
    };
    let mut ring = FrameRing::new(&gpu, gpu.queues.graphics, FRAMES_IN_FLIGHT)?;
    ring.profiler
        .add_note(format!("queue plan: {}", gpu.queues.describe()));
    for line in technique.iter().flat_map(|t| t.describe()) {
        ring.profiler.add_note(line);
    }
    if technique.is_some() {
        ring.profiler
            .add_note(format!("colour channels: {:?} plan", frame.channel_plan()));
    }
    for _ in 0..frames {
        // Shorten the boxed object's lifetime to this frame's borrow.
        let gi = technique.as_mut().map(|t| t.as_mut() as &mut dyn Technique);
        frame.submit(&gpu, &mut ring, gi)?;
    }
    ring.finish()?;
    check_validation(&gpu)?;

    let size = (frame.options.width, frame.options.height);
    output::write_images(
        args.out.as_deref(),
        args.hdr.as_deref(),
        || Ok(frame.read_ldr(&gpu)?),
        || Ok(HdrImage::new(size.0, size.1, frame.read_hdr(&gpu)?)),
        size,
    )?;
    if args.out.is_none() && args.hdr.is_none() && !args.profile.wanted() {
        log::warn!("neither --out nor --hdr given: the render was not saved");
    }
    output::write_profile(&args.profile, &ring.profiler)?;
    check_validation(&gpu)
}

/// Fail the run if the validation layers reported errors.
pub fn check_validation(gpu: &Gpu) -> anyhow::Result<()> {
    let errors = gpu.validation_errors();
    if errors > 0 {
        anyhow::bail!("the Vulkan validation layers reported {errors} error(s) (logged above)");
    }
    Ok(())
}
