//! Reading and writing images and reports. Every file is written to a temporary name in the
//! destination folder and renamed into place, so nothing is ever left half-written; outputs go
//! only to regular files (an existing symlink, FIFO, device or folder at the destination is
//! refused), and a temporary file left by a killed process is removed on the next write of the
//! same name.

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

/// Refuse a destination that exists and is not a regular file: renaming over a symlink, FIFO or
/// device node would replace it (as root, `--out /dev/null` would replace /dev/null).
pub fn check_destination(path: &Path) -> Result<(), InputError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => Err(InputError::new(format!(
            "{}: is a symbolic link; vkgi writes only regular files (remove it or choose another name)",
            path.display()
        ))),
        Ok(m) if !m.is_file() => Err(InputError::new(format!(
            "{}: exists and is not a regular file (a folder, FIFO, socket or device); vkgi writes only regular files",
            path.display()
        ))),
        _ => Ok(()),
    }
}

/// The folder `path` is written into, which must exist.
fn destination_folder(path: &Path) -> Result<PathBuf, InputError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(InputError::new(format!(
            "cannot write {}: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    Ok(dir)
}

/// Whether process `pid` still runs (Linux: it has a /proc entry). None where that cannot be
/// told, so nothing is removed there.
fn process_alive(pid: u32) -> Option<bool> {
    Path::new("/proc/self")
        .exists()
        .then(|| Path::new(&format!("/proc/{pid}")).exists())
}

/// Remove `.NAME.tmp-PID` files in `dir` whose process no longer runs (a SIGKILL mid-write).
fn remove_stale_temporaries(dir: &Path, file_name: &str) {
    let prefix = format!(".{file_name}.tmp-");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let pid = name
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix))
            .and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid
            && pid != std::process::id()
            && process_alive(pid) == Some(false)
        {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Run `write` on a temporary path next to `path`, then rename it to `path`.
pub fn write_atomically<F>(path: &Path, write: F) -> anyhow::Result<()>
where
    F: FnOnce(&Path) -> anyhow::Result<()>,
{
    let file_name = path
        .file_name()
        .ok_or_else(|| InputError::new(format!("{}: not a file path", path.display())))?
        .to_string_lossy()
        .into_owned();
    let dir = destination_folder(path)?;
    check_destination(path)?;
    remove_stale_temporaries(&dir, &file_name);
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    // Whatever sits at the temporary name (a symlink planted there, say) is not followed.
    let _ = std::fs::remove_file(&tmp);
    let result = write(&tmp).and_then(|()| {
        check_destination(path)?;
        std::fs::rename(&tmp, path)
            .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// What an image output holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// Tone-mapped 8-bit sRGB: PNG or JPEG, chosen by the extension.
    Ldr,
    /// Linear radiance: OpenEXR.
    Hdr,
}

/// The format `path`'s extension asks for, if vkgi writes that kind there.
fn output_format(path: &Path, kind: ImageKind) -> Result<ImageFormat, InputError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match (kind, extension.as_deref()) {
        (ImageKind::Ldr, Some("png")) => Ok(ImageFormat::Png),
        (ImageKind::Ldr, Some("jpg" | "jpeg")) => Ok(ImageFormat::Jpeg),
        (ImageKind::Hdr, Some("exr")) => Ok(ImageFormat::OpenExr),
        (ImageKind::Ldr, _) => Err(InputError::new(format!(
            "{}: tone-mapped images are written as PNG (.png) or JPEG (.jpg, .jpeg); name the file so",
            path.display()
        ))),
        (ImageKind::Hdr, _) => Err(InputError::new(format!(
            "{}: linear radiance is written as OpenEXR; name the file .exr",
            path.display()
        ))),
    }
}

/// Check, before any work, that an image can be written to `path`: a known extension for its
/// kind, an existing folder, and no special file or symlink in the way.
pub fn check_image_output(path: &Path, kind: ImageKind) -> Result<(), InputError> {
    output_format(path, kind)?;
    destination_folder(path)?;
    check_destination(path)
}

/// Write text (JSON, CSV, Markdown) atomically.
pub fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, text).with_context(|| format!("writing {}", path.display()))
    })
}

/// Write 8-bit RGBA pixels as RGB, PNG or JPEG by the extension.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> anyhow::Result<()> {
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let image = RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| anyhow::anyhow!("pixel buffer does not match {width}x{height}"))?;
    write_rgb(path, &image)
}

/// Write an RGB image, PNG or JPEG by the extension.
pub fn write_rgb(path: &Path, image: &RgbImage) -> anyhow::Result<()> {
    let format = output_format(path, ImageKind::Ldr)?;
    write_atomically(path, |tmp| {
        image
            .save_with_format(tmp, format)
            .with_context(|| format!("writing {}", path.display()))
    })
}

/// Write linear radiance as a 32-bit float OpenEXR.
pub fn write_exr(path: &Path, image: &HdrImage) -> anyhow::Result<()> {
    let format = output_format(path, ImageKind::Hdr)?;
    let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
    let exr = Rgb32FImage::from_raw(image.width, image.height, data)
        .ok_or_else(|| anyhow::anyhow!("pixel buffer does not match the image size"))?;
    write_atomically(path, |tmp| {
        exr.save_with_format(tmp, format)
            .with_context(|| format!("writing OpenEXR {}", path.display()))
    })
}

/// Read linear radiance: an OpenEXR (any floating-point image the image crate decodes). An
/// 8- or 16-bit image holds tone-mapped values, not radiance, and is refused unless `allow_ldr`
/// (then its values are taken as they are).
pub fn read_hdr(path: &Path, allow_ldr: bool) -> Result<HdrImage, InputError> {
    if !path.is_file() {
        return Err(InputError::new(format!("{}: no such file", path.display())));
    }
    let decoded = image::open(path)
        .map_err(|e| InputError::new(format!("{}: cannot read image: {e}", path.display())))?;
    let linear = matches!(
        decoded.color(),
        image::ColorType::Rgb32F | image::ColorType::Rgba32F
    );
    if !linear && !allow_ldr {
        return Err(InputError::new(format!(
            "{}: a {:?} image holds tone-mapped values, not linear radiance; compare linear HDR images (.exr), or pass --allow-ldr to score it anyway",
            path.display(),
            decoded.color()
        )));
    }
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
        assert_eq!(read_hdr(&path, false).unwrap(), image);
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("vkgi-imageio-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn outputs_replace_only_regular_files() {
        let dir = scratch("special");
        let target = dir.join("target.txt");
        std::fs::write(&target, "keep").unwrap();
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let err = write_text(&link, "{}").unwrap_err();
        assert!(err.downcast_ref::<InputError>().is_some(), "{err}");
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        let folder = dir.join("folder.json");
        std::fs::create_dir(&folder).unwrap();
        assert!(write_text(&folder, "{}").is_err());
        let fifo = dir.join("fifo.json");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            assert!(write_text(&fifo, "{}").is_err());
            assert!(!std::fs::symlink_metadata(&fifo).unwrap().is_file());
        }
        let regular = dir.join("plain.json");
        write_text(&regular, "1").unwrap();
        write_text(&regular, "2").unwrap();
        assert_eq!(std::fs::read_to_string(&regular).unwrap(), "2");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_dead_process_temporary_is_removed_on_the_next_write() {
        let dir = scratch("stale");
        // PID 0x7fff_fff0 is above Linux's pid_max, so no such process runs.
        let stale = dir.join(".out.json.tmp-2147483632");
        std::fs::write(&stale, "half").unwrap();
        let live = dir.join(format!(".out.json.tmp-{}", std::process::id()));
        write_text(&dir.join("out.json"), "{}").unwrap();
        assert!(!stale.exists(), "the stale temporary is gone");
        assert!(!live.exists(), "no temporary of this process is left");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn output_formats_follow_the_extension() {
        let dir = scratch("formats");
        let rgba = vec![200u8; 4 * 4 * 4];
        write_png(&dir.join("a.jpg"), 4, 4, &rgba).unwrap();
        let bytes = std::fs::read(dir.join("a.jpg")).unwrap();
        assert_eq!(&bytes[..2], &[0xFF, 0xD8], "JPEG bytes under a .jpg name");
        write_png(&dir.join("a.PNG"), 4, 4, &rgba).unwrap();
        assert!(write_png(&dir.join("a.bmp"), 4, 4, &rgba).is_err());
        let hdr = HdrImage::new(1, 1, vec![[1.0; 3]]);
        assert!(write_exr(&dir.join("a.png"), &hdr).is_err());
        assert!(
            read_hdr(&dir.join("a.PNG"), false).is_err(),
            "8-bit input refused"
        );
        assert!(read_hdr(&dir.join("a.PNG"), true).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_folder_is_an_input_error() {
        let err = write_text(Path::new("/nonexistent-vkgi-dir/x.json"), "{}").unwrap_err();
        assert!(err.downcast_ref::<InputError>().is_some());
    }
}
