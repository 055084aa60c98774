//! `vkgi compare TEST REFERENCE`: every error metric of one linear HDR image against another.

use crate::error::InputError;
use crate::imageio;
use crate::metrics;

use super::cli::CompareArgs;

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let test = imageio::read_hdr(&args.test, args.allow_ldr)?;
    let reference = imageio::read_hdr(&args.reference, args.allow_ldr)?;
    if let Some(path) = &args.json {
        imageio::check_destination(path)?;
    }
    if let Some(path) = &args.heatmap {
        imageio::check_image_output(path, imageio::ImageKind::Ldr)?;
    }
    let mask = args.mask.as_ref().map(|path| read_mask(path)).transpose()?;
    let result = metrics::compare(&test, &reference, mask.as_deref())?;
    print!("{}", result.describe());
    if let Some(path) = &args.json {
        imageio::write_text(path, &serde_json::to_string_pretty(&result)?)?;
    }
    if let Some(path) = &args.heatmap {
        let map = metrics::flip_heatmap(&test, &reference);
        imageio::write_png(path, test.width, test.height, &map)?;
    }
    Ok(())
}

/// A mask image: pixels brighter than mid-grey are counted.
fn read_mask(path: &std::path::Path) -> Result<Vec<bool>, InputError> {
    if !path.is_file() {
        return Err(InputError::new(format!("{}: no such file", path.display())));
    }
    let image = image::open(path)
        .map_err(|e| InputError::new(format!("{}: cannot read mask: {e}", path.display())))?
        .into_luma8();
    Ok(image.pixels().map(|p| p.0[0] > 127).collect())
}
