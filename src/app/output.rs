//! Writing what a run produced: images and profiles.

use std::path::Path;

use crate::gpu::Profiler;
use crate::imageio::{self, HdrImage};

use super::cli::ProfileArgs;

/// Check, before any work, that the profile's files can be written where asked.
pub fn check_profile_outputs(args: &ProfileArgs) -> Result<(), crate::error::InputError> {
    for path in [&args.profile_json, &args.trace].into_iter().flatten() {
        imageio::check_destination(path)?;
    }
    Ok(())
}

/// Print and write the profile as the arguments ask.
pub fn write_profile(args: &ProfileArgs, profiler: &Profiler) -> anyhow::Result<()> {
    let report = profiler.report();
    if args.profile {
        print!("{}", report.table());
    }
    if let Some(path) = &args.profile_json {
        imageio::write_text(path, &serde_json::to_string_pretty(&report)?)?;
    }
    if let Some(path) = &args.trace {
        imageio::write_text(path, &serde_json::to_string(&profiler.chrome_trace())?)?;
    }
    Ok(())
}

/// Write view `index` of `frame` as a tone-mapped PNG and a linear EXR.
pub fn write_view(
    gpu: &crate::gpu::Gpu,
    frame: &crate::render::Frame,
    index: usize,
    png: &Path,
    exr: &Path,
) -> anyhow::Result<()> {
    let view = &frame.views[index];
    let size = (view.width(), view.height());
    write_images(
        Some(png),
        Some(exr),
        || Ok(frame.read_view_ldr(gpu, index)?),
        || {
            Ok(HdrImage::new(
                size.0,
                size.1,
                frame.read_view_hdr(gpu, index)?,
            ))
        },
        size,
    )
}

/// Write the tone-mapped PNG and/or the linear EXR.
pub fn write_images(
    png: Option<&Path>,
    exr: Option<&Path>,
    ldr: impl FnOnce() -> anyhow::Result<Vec<u8>>,
    hdr: impl FnOnce() -> anyhow::Result<HdrImage>,
    (width, height): (u32, u32),
) -> anyhow::Result<()> {
    if let Some(path) = png {
        imageio::write_png(path, width, height, &ldr()?)?;
        log::info!("wrote {}", path.display());
    }
    if let Some(path) = exr {
        imageio::write_exr(path, &hdr()?)?;
        log::info!("wrote {}", path.display());
    }
    Ok(())
}
