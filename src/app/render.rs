//! `vkgi render`: a headless render of a scene, with or without GI, optionally profiled.

use anyhow::Context;

use crate::gpu::Gpu;
use crate::imageio::{self, HdrImage, ImageKind};
use crate::render::Frame;
use crate::render::runner::run_animation;
use crate::scene::Scene;

use super::cli::RenderArgs;
use super::{method, output};

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.out {
        imageio::check_image_output(path, ImageKind::Ldr)?;
    }
    if let Some(path) = &args.hdr {
        imageio::check_image_output(path, ImageKind::Hdr)?;
    }
    output::check_profile_outputs(&args.profile)?;
    let mut scene = Scene::load(&args.scene)?;
    scene.area_samples = args.frame.area_samples;
    log::info!("{}", scene.statistics());
    let chosen = method::choose(&args.gi.method, &args.gi.settings.values)?;
    if chosen.is_none() && args.frame.indirect_only {
        crate::bad_input!(
            "--indirect-only with --method none would render a black image: choose a GI method"
        );
    }
    let frames = args.frames.unwrap_or_else(|| {
        chosen
            .as_ref()
            .map_or(1, |c| (c.entry.settle_frames)(&c.settings))
    });
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let mut frame = Frame::new(&gpu, &scene, args.frame.options())?;
    let mut gi = method::build_if_chosen(&gpu, &scene, chosen.as_ref())?;
    let rebuild = |scene: &Scene| method::rebuild(&gpu, scene, chosen.as_ref());
    let mut ring = run_animation(&gpu, &mut frame, &mut scene, gi.as_mut(), &rebuild, frames)?;
    ring.profiler.add_note(scene.statistics());
    check_validation(&gpu)?;
    if let Some(c) = gi.as_ref().and_then(|g| g.convergence()) {
        log::info!("after {frames} frames: {} {:.3e}", c.measure, c.remaining);
    }

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
