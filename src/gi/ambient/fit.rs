//! The oracle behind the constant-ambient baseline: the per-channel irradiance E that makes
//! albedo × E / π closest (least squares) to a path-traced image of indirect light.

use glam::{Vec2, Vec3};

use crate::imageio::HdrImage;
use crate::scene::Scene;
use crate::scene::bvh::Bvh;

/// The albedo of what each pixel of the scene camera sees (0 for background), by casting one
/// ray through each pixel's centre.
pub fn albedo_image(scene: &Scene, bvh: &Bvh, width: u32, height: u32) -> Vec<[f32; 3]> {
    let epsilon = crate::reference::ray_epsilon(scene);
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let dir = scene.camera.ray_direction(pixel, width, height);
            bvh.intersect(scene.camera.position, dir, epsilon, f32::INFINITY)
                .map_or([0.0; 3], |hit| scene.albedo(hit.triangle, hit.uv).to_array())
        })
        .collect()
}

/// Per channel, the irradiance E minimising Σ (albedo · E / π − truth)² over the pixels, in
/// f64: E = π Σ a·t / Σ a² (0 where no pixel has albedo in that channel).
pub fn fit_irradiance(albedo: &[[f32; 3]], truth: &HdrImage) -> Vec3 {
    let mut numerator = [0.0f64; 3];
    let mut denominator = [0.0f64; 3];
    for (a, t) in albedo.iter().zip(&truth.pixels) {
        for c in 0..3 {
            numerator[c] += f64::from(a[c]) * f64::from(t[c]);
            denominator[c] += f64::from(a[c]) * f64::from(a[c]);
        }
    }
    let channel = |c: usize| {
        if denominator[c] > 0.0 {
            (std::f64::consts::PI * numerator[c] / denominator[c]) as f32
        } else {
            0.0
        }
    };
    Vec3::new(channel(0), channel(1), channel(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_recovers_an_exact_constant_per_channel() {
        let albedo = vec![[0.5, 0.2, 0.0], [0.25, 0.8, 0.0], [0.0, 0.0, 0.0]];
        let e = [2.0f32, 3.0, 4.0];
        let truth = HdrImage::new(
            3,
            1,
            albedo
                .iter()
                .map(|a| [0, 1, 2].map(|c| a[c] * e[c] / std::f32::consts::PI))
                .collect(),
        );
        let fit = fit_irradiance(&albedo, &truth);
        assert!((fit.x - 2.0).abs() < 1e-6 && (fit.y - 3.0).abs() < 1e-6, "{fit}");
        assert_eq!(fit.z, 0.0, "no albedo in blue: nothing to fit");
    }

    #[test]
    fn the_fit_is_the_least_squares_solution() {
        // One channel, two pixels: a = (1, 2), t = (1, 1): k = (1 + 2) / (1 + 4) = 0.6.
        let albedo = vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let truth = HdrImage::new(2, 1, vec![[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        let fit = fit_irradiance(&albedo, &truth);
        assert!((fit.x / std::f32::consts::PI - 0.6).abs() < 1e-6);
    }
}
