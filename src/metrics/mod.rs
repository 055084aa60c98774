//! Error metrics between a test image and a reference, on linear HDR images of equal size:
//! RMSE, relative MSE `(a-b)²/(b²+0.01)`, MAE, and FLIP (NVIDIA's perceptual metric, computed
//! by the official implementation through the `nv-flip` crate on both images tone-mapped the
//! way vkgi's PNGs are: Reinhard L/(1+L) and sRGB). Beside them, seed 002's "% similar" (the
//! LightWave thesis's Algorithm 1 as its script computes it, spec 002 §5): the mean over every
//! 8-bit RGB value of (smaller + 1)/(larger + 1), on the same tone-mapped bytes. An optional
//! mask restricts every metric to the pixels a method models.

pub mod plot;

use serde::Serialize;

use crate::error::InputError;
use crate::imageio::HdrImage;

/// FLIP's default observer: 0.7 m from a 0.7 m wide 4K display (67 pixels per degree).
pub const PIXELS_PER_DEGREE: f32 = 67.0;

#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Metrics {
    pub rmse: f64,
    pub rel_mse: f64,
    pub mae: f64,
    /// Mean FLIP error over the counted pixels, in [0, 1].
    pub flip: f64,
    /// Seed 002's similarity in [0, 1] (1: the same bytes); the thesis prints it × 100.
    pub similarity: f64,
    /// Pixels counted (all, or those inside the mask).
    pub pixels: usize,
}

impl Metrics {
    pub fn describe(&self) -> String {
        format!(
            "RMSE {:.6}\nrelMSE {:.6}\nMAE {:.6}\nFLIP {:.6}\nsimilarity {:.3}%\npixels {}\n",
            self.rmse,
            self.rel_mse,
            self.mae,
            self.flip,
            100.0 * self.similarity,
            self.pixels
        )
    }
}

/// The reference tone mapping of vkgi's PNG output (exposure 0): Reinhard, then sRGB, 8 bits.
pub fn tonemap_srgb8(image: &HdrImage) -> Vec<u8> {
    let encode = |v: f32| {
        let c = (v / (1.0 + v)).clamp(0.0, 1.0);
        let s = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5).clamp(0.0, 255.0) as u8
    };
    image
        .pixels
        .iter()
        .flat_map(|p| p.map(|v| encode(v.max(0.0))))
        .collect()
}

/// Per-pixel FLIP error map (row-major, in [0, 1]) of `test` against `reference`.
pub fn flip_map(test: &HdrImage, reference: &HdrImage) -> Vec<f32> {
    let (w, h) = (reference.width, reference.height);
    let reference = nv_flip::FlipImageRgb8::with_data(w, h, &tonemap_srgb8(reference));
    let test = nv_flip::FlipImageRgb8::with_data(w, h, &tonemap_srgb8(test));
    nv_flip::flip(reference, test, PIXELS_PER_DEGREE).to_vec()
}

/// The FLIP error map as an RGBA8 heat map (magma colour map, as the FLIP tool draws it).
pub fn flip_heatmap(test: &HdrImage, reference: &HdrImage) -> Vec<u8> {
    let (w, h) = (reference.width, reference.height);
    let map = nv_flip::FlipImageFloat::with_data(w, h, &flip_map(test, reference));
    map.apply_color_lut(&nv_flip::magma_lut())
        .to_vec()
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect()
}

fn check(test: &HdrImage, reference: &HdrImage, mask: Option<&[bool]>) -> Result<(), InputError> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(InputError::new(format!(
            "image sizes differ: {}x{} against a {}x{} reference",
            test.width, test.height, reference.width, reference.height
        )));
    }
    for (name, image) in [("test", test), ("reference", reference)] {
        if let Some(i) = image
            .pixels
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()))
        {
            let (x, y) = (i as u32 % image.width, i as u32 / image.width);
            return Err(InputError::new(format!(
                "the {name} image has a non-finite pixel at ({x}, {y})"
            )));
        }
    }
    if let Some(mask) = mask {
        if mask.len() != reference.pixels.len() {
            return Err(InputError::new("the mask's size differs from the images'"));
        }
        if !mask.iter().any(|&m| m) {
            return Err(InputError::new("the mask selects no pixel"));
        }
    }
    Ok(())
}

/// Every metric of `test` against `reference`, over the pixels `mask` selects (all if None).
pub fn compare(
    test: &HdrImage,
    reference: &HdrImage,
    mask: Option<&[bool]>,
) -> Result<Metrics, InputError> {
    check(test, reference, mask)?;
    let flip = flip_map(test, reference);
    let counted = |i: usize| mask.is_none_or(|m| m[i]);
    let (mut se, mut rel, mut ae, mut flip_sum) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut pixels = 0usize;
    for (i, (a, b)) in test.pixels.iter().zip(&reference.pixels).enumerate() {
        if !counted(i) {
            continue;
        }
        pixels += 1;
        flip_sum += f64::from(flip[i]);
        for c in 0..3 {
            let (a, b) = (f64::from(a[c]), f64::from(b[c]));
            let d = a - b;
            se += d * d;
            rel += d * d / (b * b + 0.01);
            ae += d.abs();
        }
    }
    let values = (3 * pixels) as f64;
    Ok(Metrics {
        rmse: (se / values).sqrt(),
        rel_mse: rel / values,
        mae: ae / values,
        flip: flip_sum / pixels as f64,
        similarity: similarity(test, reference, mask)?,
        pixels,
    })
}

/// Seed 002's similarity of `test` to `reference` over the pixels `mask` selects: the mean of
/// `byte_similarity` over their tone-mapped RGB bytes.
pub fn similarity(
    test: &HdrImage,
    reference: &HdrImage,
    mask: Option<&[bool]>,
) -> Result<f64, InputError> {
    check(test, reference, mask)?;
    let (mut a, mut b) = (tonemap_srgb8(test), tonemap_srgb8(reference));
    if let Some(mask) = mask {
        let keep = |bytes: &[u8]| -> Vec<u8> {
            bytes
                .chunks_exact(3)
                .zip(mask)
                .filter(|(_, m)| **m)
                .flat_map(|(p, _)| p.iter().copied())
                .collect()
        };
        (a, b) = (keep(&a), keep(&b));
    }
    Ok(similarity_of_bytes(&a, &b))
}

/// Seed 002's similarity of two 8-bit images of equal size (the thesis's script works on the
/// bytes of its screenshots): the mean of `byte_similarity` over every value; 1 for no value.
pub fn similarity_of_bytes(test: &[u8], reference: &[u8]) -> f64 {
    if test.is_empty() {
        return 1.0;
    }
    let sum: f64 = test
        .iter()
        .zip(reference)
        .map(|(&a, &b)| byte_similarity(a, b))
        .sum();
    sum / test.len() as f64
}

/// Seed 002's per-value similarity: (smaller + 1)/(larger + 1), so 200 against 100 is about
/// 50% similar (the thesis's worked example; its printed pseudo-code has the ratio inverted).
fn byte_similarity(a: u8, b: u8) -> f64 {
    (f64::from(a.min(b)) + 1.0) / (f64::from(a.max(b)) + 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 3]) -> HdrImage {
        HdrImage::new(
            w,
            h,
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| f(x, y))
                .collect(),
        )
    }

    #[test]
    fn numeric_metrics_match_hand_computed_values() {
        let reference = image(2, 1, |_, _| [1.0, 1.0, 1.0]);
        let test = image(2, 1, |x, _| if x == 0 { [1.0; 3] } else { [3.0, 1.0, 1.0] });
        let m = compare(&test, &reference, None).unwrap();
        // One channel of six differs by 2.
        assert!((m.rmse - (4.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((m.mae - 2.0 / 6.0).abs() < 1e-12);
        assert!((m.rel_mse - (4.0 / 1.01) / 6.0).abs() < 1e-12);
        assert_eq!(m.pixels, 2);
        // Tone-mapped, 1.0 and 3.0 are bytes 188 and 225: one value of six is 189/226 similar.
        assert_eq!(tonemap_srgb8(&test)[3..6], [225, 188, 188]);
        assert!((m.similarity - (5.0 + 189.0 / 226.0) / 6.0).abs() < 1e-12);
        assert_eq!(
            compare(&reference, &reference, None).unwrap().similarity,
            1.0
        );
        assert!((byte_similarity(200, 100) - 101.0 / 201.0).abs() < 1e-15);
        assert_eq!(byte_similarity(0, 255), 1.0 / 256.0);
        let masked = |m: &[bool]| similarity(&test, &reference, Some(m)).unwrap();
        assert_eq!(masked(&[true, false]), 1.0);
        assert!((masked(&[false, true]) - (2.0 + 189.0 / 226.0) / 3.0).abs() < 1e-12);
        let only_first = compare(&test, &reference, Some(&[true, false])).unwrap();
        assert_eq!(
            (only_first.rmse, only_first.mae, only_first.pixels),
            (0.0, 0.0, 1)
        );
        // FLIP filters spatially, so the neighbour's difference reaches the masked-in pixel.
        assert_eq!(only_first.flip, f64::from(flip_map(&test, &reference)[0]));
    }

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_the_difference() {
        let reference = image(64, 64, |x, y| [x as f32 / 64.0, y as f32 / 64.0, 0.3]);
        assert_eq!(compare(&reference, &reference, None).unwrap().flip, 0.0);
        let noisy = |amplitude: f32| {
            image(64, 64, |x, y| {
                let n = if (x * 7 + y * 13) % 3 == 0 {
                    amplitude
                } else {
                    -amplitude
                };
                [(x as f32 / 64.0 + n).max(0.0), y as f32 / 64.0, 0.3]
            })
        };
        let small = compare(&noisy(0.02), &reference, None).unwrap().flip;
        let large = compare(&noisy(0.3), &reference, None).unwrap().flip;
        assert!(
            0.0 < small && small < large && large < 1.0,
            "{small} {large}"
        );
        // Black against white is (nearly) the largest difference FLIP knows.
        let black = image(32, 32, |_, _| [0.0; 3]);
        let white = image(32, 32, |_, _| [1e6; 3]);
        assert!(compare(&black, &white, None).unwrap().flip > 0.9);
    }

    #[test]
    fn bad_inputs_are_clear_errors() {
        let a = image(2, 2, |_, _| [0.0; 3]);
        let b = image(2, 3, |_, _| [0.0; 3]);
        assert!(
            compare(&a, &b, None)
                .unwrap_err()
                .to_string()
                .contains("sizes differ")
        );
        let nan = image(2, 2, |x, _| if x == 1 { [f32::NAN; 3] } else { [0.0; 3] });
        assert!(
            compare(&nan, &a, None)
                .unwrap_err()
                .to_string()
                .contains("non-finite")
        );
        assert!(
            compare(&a, &a, Some(&[false; 4]))
                .unwrap_err()
                .to_string()
                .contains("no pixel")
        );
    }
}
