//! The surface model every renderer in vkgi shares: a Lambertian lobe `albedo / π` plus a glossy
//! microfacet lobe `specular · D(h) G(l, v) / (4 (n·l)(n·v))` with the GGX distribution
//! (α = roughness²), the separable Smith shadowing term and no Fresnel factor: `specular` is the
//! lobe's reflectance at every angle (glTF's F0; MTL's Ks). shaders-glsl/common/brdf.glsl is the
//! same arithmetic; the path tracer samples the glossy lobe by its distribution of normals.

use glam::Vec3;

/// The smallest roughness rendered (α = 0.01); mirrors are out of scope.
pub const MIN_ROUGHNESS: f32 = 0.1;

/// The GGX width of a perceptual roughness.
pub fn alpha(roughness: f32) -> f32 {
    roughness * roughness
}

/// The perceptual roughness whose GGX lobe matches a Phong exponent `ns` (the usual
/// correspondence α² = 2 / (ns + 2)), clamped to the rendered range.
pub fn roughness_from_phong(ns: f32) -> f32 {
    (2.0 / (ns.max(0.0) + 2.0))
        .sqrt()
        .sqrt()
        .clamp(MIN_ROUGHNESS, 1.0)
}

/// The Phong exponent [`roughness_from_phong`] turns into `roughness`.
pub fn phong_from_roughness(roughness: f32) -> f32 {
    2.0 / alpha(roughness).powi(2) - 2.0
}

/// GGX normal distribution at cos θ_h = `n_h` for α² = `a2`.
pub fn ggx_d(n_h: f32, a2: f32) -> f32 {
    let d = n_h * n_h * (a2 - 1.0) + 1.0;
    a2 / (std::f32::consts::PI * d * d)
}

/// Smith's masking of one direction at cos θ = `n_x`.
pub fn smith_g1(n_x: f32, a2: f32) -> f32 {
    2.0 * n_x / (n_x + (a2 + (1.0 - a2) * n_x * n_x).sqrt())
}

/// The glossy lobe times n·l for light from `l` seen from `v` (unit vectors, `n` the normal).
pub fn glossy_cos(specular: Vec3, roughness: f32, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    let (n_l, n_v) = (n.dot(l), n.dot(v));
    if n_l <= 0.0 || n_v <= 0.0 {
        return Vec3::ZERO;
    }
    let a2 = alpha(roughness) * alpha(roughness);
    let h = (l + v).normalize();
    let n_h = n.dot(h).max(0.0);
    specular * (ggx_d(n_h, a2) * smith_g1(n_l, a2) * smith_g1(n_v, a2) / (4.0 * n_v))
}

/// Density (solid angle) of [`sample_glossy`] choosing `l`.
pub fn glossy_pdf(roughness: f32, n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let h = (l + v).normalize();
    let (n_h, v_h) = (n.dot(h), v.dot(h));
    if n_h <= 0.0 || v_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha(roughness) * alpha(roughness);
    ggx_d(n_h, a2) * n_h / (4.0 * v_h)
}

/// A direction reflected about a GGX normal drawn by D(h)(n·h) from two uniform numbers
/// (as `sample_glossy` in brdf.glsl; `basis` is the tangent frame of `n`).
pub fn sample_glossy(
    roughness: f32,
    (t, b, n): (Vec3, Vec3, Vec3),
    v: Vec3,
    u1: f32,
    u2: f32,
) -> Vec3 {
    let a2 = alpha(roughness) * alpha(roughness);
    let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    let cos_h = cos2.max(0.0).sqrt();
    let sin_h = (1.0 - cos2).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    let h = (t * (sin_h * phi.cos()) + b * (sin_h * phi.sin()) + n * cos_h).normalize();
    (h * (2.0 * v.dot(h)) - v).normalize()
}

/// How often a path tracer bounces by the glossy lobe: its share of the mean reflectance
/// (0 for Lambertian surfaces, whose bounces stay cosine-weighted).
pub fn glossy_share(albedo: Vec3, specular: Vec3) -> f32 {
    let s = specular.x + specular.y + specular.z;
    let d = albedo.x + albedo.y + albedo.z;
    if s > 0.0 { s / (s + d) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn basis(n: Vec3) -> (Vec3, Vec3, Vec3) {
        let (t, b) = n.any_orthonormal_pair();
        (t, b, n)
    }

    /// The directions of a fine (θ, φ) grid over the sphere with their solid angles.
    fn sphere(steps: usize) -> Vec<(Vec3, f32)> {
        let mut out = Vec::new();
        for i in 0..steps {
            for j in 0..2 * steps {
                let (t0, t1) = (
                    std::f64::consts::PI * i as f64 / steps as f64,
                    std::f64::consts::PI * (i + 1) as f64 / steps as f64,
                );
                let phi = std::f64::consts::PI * (j as f64 + 0.5) / steps as f64;
                let theta = 0.5 * (t0 + t1);
                let d = glam::DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let area = (t0.cos() - t1.cos()) * std::f64::consts::PI / steps as f64;
                out.push((d.as_vec3(), area as f32));
            }
        }
        out
    }

    #[test]
    fn the_sampling_density_integrates_to_one_and_the_lobe_loses_energy_only_to_shadowing() {
        let n = Vec3::Z;
        for roughness in [0.3, 0.6, 1.0] {
            for tilt in [0.0f32, 0.7, 1.2] {
                let v = Vec3::new(tilt.sin(), 0.0, tilt.cos());
                let (mut pdf, mut albedo) = (0.0f64, 0.0f64);
                for (l, area) in sphere(600) {
                    pdf += (glossy_pdf(roughness, n, l, v) * area) as f64;
                    albedo += (glossy_cos(Vec3::ONE, roughness, n, l, v).x * area) as f64;
                }
                // Sampled normals facing away from v are lost, so the integral is at most 1
                // (0.68 at roughness 1, 69 degrees); single-scattering GGX loses much of a rough
                // lobe (0.31 at roughness 1, normal incidence).
                assert!(
                    pdf <= 1.0 + 2e-3 && pdf > 0.6,
                    "r {roughness} tilt {tilt}: {pdf}"
                );
                assert!(
                    albedo <= 1.0 + 2e-3 && albedo > 0.25,
                    "r {roughness} tilt {tilt}: {albedo}"
                );
            }
        }
    }

    #[test]
    fn sampled_directions_follow_the_density() {
        // Histogram of sampled cos θ_l against the density integrated over the same bins.
        let (n, v) = (Vec3::Z, Vec3::new(0.6, 0.0, 0.8));
        let roughness = 0.5;
        let bins = 8;
        let mut counts = vec![0.0f64; bins];
        let samples = 200_000;
        let mut rng = 0x2545_f491u32;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            (rng >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..samples {
            let l = sample_glossy(roughness, basis(n), v, next(), next());
            if l.z > 0.0 {
                counts[((l.z * bins as f32) as usize).min(bins - 1)] += 1.0 / samples as f64;
            }
        }
        let mut expected = vec![0.0f64; bins];
        for (l, area) in sphere(800) {
            if l.z > 0.0 {
                expected[((l.z * bins as f32) as usize).min(bins - 1)] +=
                    (glossy_pdf(roughness, n, l, v) * area) as f64;
            }
        }
        for (c, e) in counts.iter().zip(&expected) {
            assert!(
                (c - e).abs() < 0.01 + 0.03 * e,
                "{counts:?} vs {expected:?}"
            );
        }
    }

    #[test]
    fn phong_exponents_map_onto_the_roughness_range() {
        assert_eq!(roughness_from_phong(0.0), 1.0);
        assert!((alpha(roughness_from_phong(98.0)).powi(2) - 0.02).abs() < 1e-6);
        assert_eq!(roughness_from_phong(1e9), MIN_ROUGHNESS);
        for r in [0.1, 0.35, 0.8, 1.0] {
            assert!((roughness_from_phong(phong_from_roughness(r)) - r).abs() < 1e-5);
        }
        assert_eq!(glossy_share(Vec3::ONE, Vec3::ZERO), 0.0);
    }
}
