//! `vkgi reference`: the ground-truth path-traced image, with its settings beside it.

use std::time::Instant;

use anyhow::Context;

use crate::gpu::Gpu;
use crate::imageio;
use crate::reference::cache::{self, CacheRecord};
use crate::reference::{self, ReferenceSettings};
use crate::scene::Scene;

use super::cli::ReferenceArgs;

pub fn run(args: &ReferenceArgs) -> anyhow::Result<()> {
    imageio::check_image_output(&args.out, imageio::ImageKind::Hdr)?;
    if let Some(png) = &args.png {
        imageio::check_image_output(png, imageio::ImageKind::Ldr)?;
    }
    let mut scene = Scene::load(&args.scene)?;
    if scene.dynamic.is_empty() && args.frame > 0 {
        log::warn!(
            "--frame {} poses nothing: the scene has no dynamic objects",
            args.frame
        );
    }
    scene.pose(args.frame);
    if args.spp == 0 {
        crate::bad_input!("--spp must be at least 1");
    }
    let settings = ReferenceSettings {
        width: args.size.0,
        height: args.size.1,
        spp: args.spp,
        bounces: args.bounces,
        seed: args.seed,
        strategy: args.strategy,
    };
    let key = cache::key(&scene, &settings);
    if args.reuse && args.split && cache::load(&args.out, &key).is_some() {
        eprintln!(
            "{}: reusing the cached reference (same scene, settings and code)",
            args.out.display()
        );
        return Ok(());
    }
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let bar = super::progress::counting("reference", "spp");
    let start = Instant::now();
    let (images, traced_on) =
        reference::trace(&gpu, &scene, &settings, args.tracer, |done, total| {
            super::progress::update(&bar, done, total)
        })?;
    let seconds = start.elapsed().as_secs_f64();
    super::render::check_validation(&gpu)?;
    let record = CacheRecord {
        key,
        split: args.split,
        seconds,
        device: traced_on.clone(),
    };
    cache::store(&args.out, &images, &record)?;
    if let Some(png) = &args.png {
        let combined = images.combined();
        let scale = args.exposure.exp2();
        let exposed = imageio::HdrImage::new(
            combined.width,
            combined.height,
            combined
                .pixels
                .iter()
                .map(|p| p.map(|v| v * scale))
                .collect(),
        );
        let rgb = crate::metrics::tonemap_srgb8(&exposed);
        let rgba: Vec<u8> = rgb
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        imageio::write_png(png, combined.width, combined.height, &rgba)?;
    }
    eprintln!(
        "reference: {}x{} at {} spp in {seconds:.1} s on {} -> {}",
        settings.width,
        settings.height,
        settings.spp,
        traced_on,
        args.out.display()
    );
    Ok(())
}
