//! What the plotting benches share (each uses a part of it).
#![allow(dead_code)]

use std::path::PathBuf;

use vkgi::gpu::Gpu;
use vkgi::imageio::HdrImage;
use vkgi::reference::{Bounces, PathTracer, ReferenceSettings};
use vkgi::scene::Scene;

/// The folder for a bench's plots: its first argument that is not a flag (cargo bench passes
/// `--bench`), docs/images by default; created if missing.
pub fn out_dir() -> anyhow::Result<PathBuf> {
    let dir = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with("--"))
        .map_or_else(|| PathBuf::from("docs/images"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

/// The path tracer's indirect light of `scene` with one indirect bounce (the part LPV models),
/// `size` pixels at `spp` samples per pixel.
pub fn indirect_reference(
    gpu: &Gpu,
    scene: &Scene,
    size: (u32, u32),
    spp: u32,
) -> anyhow::Result<HdrImage> {
    let settings = ReferenceSettings {
        width: size.0,
        height: size.1,
        spp,
        bounces: Bounces::Limited(1),
        seed: 1,
        strategy: Default::default(),
    };
    let mut tracer = PathTracer::new(gpu, scene, size.0, size.1)?;
    Ok(tracer.render(gpu, &settings, |_, _| {})?.indirect)
}
