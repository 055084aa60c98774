//! Reading and writing images and reports. Every file is written to a temporary name in the
//! destination folder and renamed into place, so nothing is ever left half-written.

use std::path::{Path, PathBuf};

use anyhow::Context;
use image::{ImageFormat, Rgb32FImage, RgbImage};

use crate::error::InputError;

/// A linear HDR RGB image, row-major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl HdrImage {
    pub fn new(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Self {
        debug_assert_eq!(pixels.len(), (width * height) as usize);
        HdrImage {
            width,
            height,
            pixels,
        }
    }

    pub fn at(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[(y * self.width + x) as usize]
    }
}

/// Run `write` on a temporary path next to `path`, then rename it to `path`.
pub fn write_atomically<F>(path: &Path, write: F) -> anyhow::Result<()>
where
    F: FnOnce(&Path) -> anyhow::Result<()>,
{
    let file_name = path
        .file_name()
        .ok_or_else(|| InputError::new(format!("{}: not a file path", path.display())))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(InputError::new(format!(
            "cannot write {}: folder {} does not exist",
            path.display(),
            dir.display()
        ))
        .into());
    }
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let result = write(&tmp).and_then(|()| {
        std::fs::rename(&tmp, path)
            .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Write text (JSON, CSV, Markdown) atomically.
pub fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, text).with_context(|| format!("writing {}", path.display()))
    })
}

/// Write 8-bit RGBA pixels as an RGB PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> anyhow::Result<()> {
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let image = RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| anyhow::anyhow!("pixel buffer does not match {width}x{height}"))?;
    write_atomically(path, |tmp| {
        image
            .save_with_format(tmp, ImageFormat::Png)
            .with_context(|| format!("writing PNG {}", path.display()))
    })
}

/// Write linear radiance as a 32-bit float OpenEXR.
pub fn write_exr(path: &Path, image: &HdrImage) -> anyhow::Result<()> {
    let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
    let exr = Rgb32FImage::from_raw(image.width, image.height, data)
        .ok_or_else(|| anyhow::anyhow!("pixel buffer does not match the image size"))?;
    write_atomically(path, |tmp| {
        exr.save_with_format(tmp, ImageFormat::OpenExr)
            .with_context(|| format!("writing OpenEXR {}", path.display()))
    })
}

/// Read an OpenEXR (or any format the image crate decodes) as linear RGB floats.
pub fn read_hdr(path: &Path) -> Result<HdrImage, InputError> {
    if !path.is_file() {
        return Err(InputError::new(format!("{}: no such file", path.display())));
    }
    let decoded = image::open(path)
        .map_err(|e| InputError::new(format!("{}: cannot read image: {e}", path.display())))?;
    let rgb = decoded.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb.pixels().map(|p| p.0).collect();
    Ok(HdrImage::new(width, height, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trips_exactly() {
        let dir = std::env::temp_dir().join(format!("vkgi-imageio-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.exr");
        let image = HdrImage::new(
            3,
            2,
            vec![
                [0.0, 1.5, 1e6],
                [1e-7, 2.0, 3.0],
                [4.0; 3],
                [0.25; 3],
                [7.0; 3],
                [8.0, 9.0, 10.0],
            ],
        );
        write_exr(&path, &image).unwrap();
        assert_eq!(read_hdr(&path).unwrap(), image);
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_folder_is_an_input_error() {
        let err = write_text(Path::new("/nonexistent-vkgi-dir/x.json"), "{}").unwrap_err();
        assert!(err.downcast_ref::<InputError>().is_some());
    }
}
