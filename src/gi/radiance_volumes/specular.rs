//! Indirect specular from per-cache hemisphere maps (spec 001 §4.7), in f64: the map's
//! parameterisation, a cache's map filled from the VALs, and the apply pass's glossy lookup. The
//! GPU passes (light.comp fills, apply.comp looks up; shaders-glsl/gi/radiance_volumes/
//! specular.glsl) are tested against these.
//!
//! A cache's map covers the hemisphere of half vectors h around z = the direction from the cache
//! to the cascades' eye (the camera). A VAL seen along l sends its perpendicular irradiance E
//! to the texel holding h = normalize(l + z), as a density over the texel's solid angle: the
//! texel holds T(h) = Σ E / ΔΩ, the incoming light carried into the half-vector domain
//! (dω_l = 4 (v·h) dω_h). The glossy lobe of src/scene/brdf.rs then reflects toward the eye,
//! for a surface of normal n,
//!
//!   L = specular · Σ_j E_j D(h_j) G1(n·l_j) G1(n·v) / (4 n·v)
//!     = specular · G1(n·v) / (4 n·v) · ∫ T(h) D(n·h) G1(n·l(h)) dω_h
//!     ≈ specular · G1(n·v) / (4 n·v) · Σ_k T_k ⟨D(n·h) G1(n·l(h))⟩_k ΔΩ,
//!
//! ⟨⟩_k the weight at texel k's centre, or its mean over a few points of the texel where a
//! narrow lobe's core falls (see `under_lobe`). Every texel is weighted, so GGX's long tails see
//! light beside the mirror direction. Each cache's map is read in its own frame, with the
//! pixel's normal. The approximations beyond the texels' size: light is constant within a
//! texel, and a cache's eye direction stands for the pixel's.
//!
//! The parameterisation is the concentric square map of the Lambert equal-area disc: every
//! texel of a P×P map subtends exactly 2π/P² sr.

use glam::DVec3;

use super::cpu::Val;
use crate::scene::brdf;

/// Where unit `h` (h.z ≥ 0) falls in the unit square.
pub fn map(h: DVec3) -> (f64, f64) {
    let r = 0.5 * (1.0 - h.z.min(1.0)).max(0.0).sqrt();
    if r == 0.0 {
        return (0.5, 0.5);
    }
    let mut phi = h.y.atan2(h.x) * 4.0 / std::f64::consts::PI;
    if phi < -1.0 {
        phi += 8.0;
    }
    let (a, b) = if phi < 1.0 {
        (r, phi * r)
    } else if phi < 3.0 {
        (-(phi - 2.0) * r, r)
    } else if phi < 5.0 {
        (-r, -(phi - 4.0) * r)
    } else {
        ((phi - 6.0) * r, -r)
    };
    (a + 0.5, b + 0.5)
}

/// The direction [`map`] sends to `(u, v)`.
pub fn unmap(u: f64, v: f64) -> DVec3 {
    let (a, b) = (u - 0.5, v - 0.5);
    let r = a.abs().max(b.abs());
    if r == 0.0 {
        return DVec3::Z;
    }
    let phi = if a.abs() >= b.abs() {
        if a > 0.0 { b / r } else { 4.0 - b / r }
    } else if b > 0.0 {
        2.0 - a / r
    } else {
        6.0 + a / r
    } * std::f64::consts::PI
        / 4.0;
    let z = 1.0 - 4.0 * r * r;
    let s = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// The cache-local frame (tangent, bitangent, z) around unit `z`: the Duff et al. basis, as
/// `orthonormal_basis` in sampling.glsl.
pub fn frame(z: DVec3) -> (DVec3, DVec3, DVec3) {
    let s = if z.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + z.z);
    let c = z.x * z.y * a;
    let t = DVec3::new(1.0 + s * z.x * z.x * a, s * c, -s * z.x);
    let b = DVec3::new(c, s + z.y * z.y * a, -z.y);
    (t, b, z)
}

fn local(d: DVec3, (t, b, z): (DVec3, DVec3, DVec3)) -> DVec3 {
    DVec3::new(d.dot(t), d.dot(b), d.dot(z))
}

/// One cache's hemisphere map (rows of `side` texels).
#[derive(Clone, Debug, PartialEq)]
pub struct HemisphereMap {
    pub side: u32,
    pub texels: Vec<DVec3>,
}

impl HemisphereMap {
    /// The map of a cache at `x` seen from `eye`, from every VAL (times `visibility(j)`).
    pub fn fill(
        vals: &[Val],
        (x, eye): (DVec3, DVec3),
        side: u32,
        mut visibility: impl FnMut(usize) -> f64,
    ) -> HemisphereMap {
        let mut texels = vec![DVec3::ZERO; (side * side) as usize];
        let basis = frame((eye - x).normalize_or(DVec3::Z));
        let density = f64::from(side * side) / (2.0 * std::f64::consts::PI);
        for (j, val) in vals.iter().enumerate() {
            let Some((w, e)) = val.perpendicular_irradiance(x) else {
                continue;
            };
            if let Some(texel) = texel_of(local(w, basis), side) {
                texels[texel] += e * (visibility(j) * density);
            }
        }
        HemisphereMap { side, texels }
    }

    /// ∫ T(h) D(n·h) G1(n·l(h)) dω_h over the map, for the GGX lobe of width `alpha` around
    /// the local normal `n`, texel by texel: each texel's weight is D·G1 at its centre, or,
    /// near a lobe narrower than the texels, the mean over [`texel_samples`]² points of it, so
    /// the lobe's core is not missed between texel centres and its tails keep their true width.
    /// l(h) is the direction h reflects the eye (local z) into; where it is below the surface
    /// nothing is reflected.
    pub fn under_lobe(&self, n: DVec3, alpha: f64) -> DVec3 {
        let a2 = (alpha * alpha) as f32;
        let side = self.side;
        let d_alpha = sampled_alpha(alpha, side);
        let d2 = (d_alpha * d_alpha) as f32;
        let samples = texel_samples(d_alpha, side);
        let near = near_cosine(d_alpha, side);
        let texel = 2.0 * std::f64::consts::PI / f64::from(side * side);
        let weight = |h: DVec3| {
            let (n_h, n_l) = (n.dot(h), n.dot(h * (2.0 * h.z) - DVec3::Z));
            if n_h > 0.0 && n_l > 0.0 {
                f64::from(brdf::ggx_d(n_h as f32, d2) * brdf::smith_g1(n_l as f32, a2))
            } else {
                0.0
            }
        };
        let mut sum = DVec3::ZERO;
        for (k, t) in self.texels.iter().enumerate() {
            let k = k as u32;
            let centre = texel_centre(k, side);
            let w = if samples > 1 && n.dot(centre) > near {
                let sub = |c: u32, s: u32| {
                    (f64::from(c) + (f64::from(s) + 0.5) / f64::from(samples)) / f64::from(side)
                };
                let mut w = 0.0;
                for j in 0..samples {
                    for i in 0..samples {
                        w += weight(unmap(sub(k % side, i), sub(k / side, j)));
                    }
                }
                w / f64::from(samples * samples)
            } else {
                weight(centre)
            };
            sum += *t * (w * texel);
        }
        sum
    }
}

/// A texel's angular size near the map's centre, in radians of half-vector angle.
fn texel_angle(side: u32) -> f64 {
    2.0 * std::f64::consts::SQRT_2 / f64::from(side)
}

/// The width D is evaluated with: the lobe's own, or, for a lobe narrower than a quarter
/// texel (roughness below 0.3 at 8²), a quarter texel, so the sub-sampled points cannot miss
/// its core. Shadowing keeps the lobe's own width.
pub fn sampled_alpha(alpha: f64, side: u32) -> f64 {
    alpha.max(texel_angle(side) / 4.0)
}

/// Points per texel side at which [`HemisphereMap::under_lobe`] evaluates a lobe of `alpha`
/// near its axis: about two per α, at most 4 (1: the centre alone).
pub fn texel_samples(alpha: f64, side: u32) -> u32 {
    ((2.0 * texel_angle(side) / alpha).ceil() as u32).clamp(1, 4)
}

/// The cosine between the lobe's axis and a texel centre above which the texel is sampled
/// finely: within a texel and 2 α of the axis.
pub fn near_cosine(alpha: f64, side: u32) -> f64 {
    (texel_angle(side) + 2.0 * alpha)
        .min(std::f64::consts::PI)
        .cos()
}

/// The direction at the centre of texel `k` of a map of `side`.
pub fn texel_centre(k: u32, side: u32) -> DVec3 {
    let s = f64::from(side);
    unmap((f64::from(k % side) + 0.5) / s, (f64::from(k / side) + 0.5) / s)
}

/// The texel holding the half vector of light from local direction `l`; None for light
/// from straight behind (no half vector).
pub fn texel_of(l: DVec3, side: u32) -> Option<usize> {
    let sum = l + DVec3::Z;
    if sum.length_squared() < 1e-12 {
        return None;
    }
    let (u, v) = map(sum.normalize());
    let s = f64::from(side);
    let (x, y) = (
        ((u * s) as u32).min(side - 1),
        ((v * s) as u32).min(side - 1),
    );
    Some((y * side + x) as usize)
}

/// The factor G1(n·v) / (4 n·v) that turns [`HemisphereMap::under_lobe`] into reflected
/// radiance per unit specular reflectance, for a surface of normal `n` at `p` seen from `eye`;
/// None where the surface faces away from the eye.
pub fn lookup_factor(p: DVec3, n: DVec3, eye: DVec3, roughness: f64) -> Option<f64> {
    let v = (eye - p).normalize_or(DVec3::Z);
    let n_v = n.dot(v);
    if n_v <= 0.0 {
        return None;
    }
    let alpha = roughness * roughness;
    let g1 = f64::from(brdf::smith_g1(n_v as f32, (alpha * alpha) as f32));
    Some(g1 / (4.0 * n_v))
}

/// A world normal in the frame of the map of a cache at `x` (every map is read in its own
/// cache's frame: no field of frames over the sphere is continuous, so a pixel's own frame
/// could be turned against its corner caches' frames).
pub fn cache_normal(n: DVec3, x: DVec3, eye: DVec3) -> DVec3 {
    local(n, frame((eye - x).normalize_or(DVec3::Z)))
}

/// The glossy light every VAL sends off a surface at `x` (normal `n`, reflectance `specular`,
/// `roughness`) toward `eye`, summed over every VAL without visibility: the ground truth of the
/// cached specular path, as [`super::cpu::gather`] is of the diffuse one.
pub fn gather(
    vals: &[Val],
    (x, n, eye): (DVec3, DVec3, DVec3),
    specular: DVec3,
    roughness: f64,
) -> DVec3 {
    let v = (eye - x).normalize_or(DVec3::Z);
    vals.iter()
        .filter_map(|val| val.perpendicular_irradiance(x))
        .map(|(w, e)| {
            let f = brdf::glossy_cos(
                glam::Vec3::ONE,
                roughness as f32,
                n.as_vec3(),
                w.as_vec3(),
                v.as_vec3(),
            );
            e * specular * f64::from(f.x)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_round_trips_directions_and_texel_centres() {
        for i in 0..40 {
            for j in 0..80 {
                let theta = std::f64::consts::FRAC_PI_2 * (i as f64 + 0.5) / 40.0;
                let phi = std::f64::consts::PI * (j as f64 + 0.5) / 40.0 - std::f64::consts::PI;
                let h = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let (u, v) = map(h);
                assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v));
                assert!((unmap(u, v) - h).length() < 1e-12, "{h} -> ({u}, {v})");
            }
        }
        for side in [4u32, 8, 16] {
            for y in 0..side {
                for x in 0..side {
                    let (u, v) = ((x as f64 + 0.5) / side as f64, (y as f64 + 0.5) / side as f64);
                    let (u2, v2) = map(unmap(u, v));
                    assert!((u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12);
                    assert_eq!(texel_of_half(unmap(u, v), side), (y * side + x) as usize);
                }
            }
        }
    }

    /// The texel holding half vector `h` (light from `l` with h = normalize(l + z)).
    fn texel_of_half(h: DVec3, side: u32) -> usize {
        texel_of(h * (2.0 * h.z) - DVec3::Z, side).unwrap()
    }

    /// Solid angle of the spherical triangle a b c (Van Oosterom and Strackee).
    fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let num = a.dot(b.cross(c)).abs();
        let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
        2.0 * num.atan2(den)
    }

    #[test]
    fn every_texel_subtends_two_pi_over_its_count_and_they_sum_to_two_pi() {
        let side = 8u32;
        let sub = 64;
        let mut total = 0.0;
        for y in 0..side {
            for x in 0..side {
                let mut texel = 0.0;
                for j in 0..sub {
                    for i in 0..sub {
                        let at = |di: usize, dj: usize| {
                            unmap(
                                (x as f64 + (i + di) as f64 / sub as f64) / side as f64,
                                (y as f64 + (j + dj) as f64 / sub as f64) / side as f64,
                            )
                        };
                        let (a, b, c, d) = (at(0, 0), at(1, 0), at(1, 1), at(0, 1));
                        texel += triangle_solid_angle(a, b, c) + triangle_solid_angle(a, c, d);
                    }
                }
                let expected = 2.0 * std::f64::consts::PI / f64::from(side * side);
                assert!((texel / expected - 1.0).abs() < 2e-3, "texel {x},{y}: {texel}");
                total += texel;
            }
        }
        assert!((total / (2.0 * std::f64::consts::PI) - 1.0).abs() < 1e-4, "{total}");
    }

    #[test]
    fn a_map_filled_with_uniform_light_reflects_it_as_the_lobe_does() {
        // Light from a fine shell of VALs, all around: every texel's density is the same
        // function of h alone, T(h) = 4 L (v·h) for radiance L, and the lookup returns about
        // specular · L · G1² at a surface facing the eye.
        let mut vals = Vec::new();
        let count = 200;
        for i in 0..count {
            for j in 0..2 * count {
                let theta = std::f64::consts::PI * (i as f64 + 0.5) / count as f64;
                let phi = std::f64::consts::PI * (j as f64 + 0.5) / count as f64;
                let d = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let solid_angle = theta.sin() * (std::f64::consts::PI / count as f64).powi(2);
                // A VAL at distance 10 facing the centre whose flux gives radiance 1 over its
                // solid angle: E = Φ / (π r²) = solid angle.
                vals.push(Val {
                    position: d * 10.0,
                    normal_sum: -d,
                    flux: DVec3::splat(solid_angle * std::f64::consts::PI * 100.0),
                    texels: 1.0,
                    ..Val::default()
                });
            }
        }
        let eye = DVec3::new(0.0, 0.0, 5.0);
        // Roughness 0.1 (α = 0.01) is far narrower than a texel: its D is evaluated a quarter
        // texel wide.
        for roughness in [0.1, 0.35, 0.6, 1.0] {
            // The lobe's directional albedo at normal incidence: the exact answer.
            let albedo: f64 = vals
                .iter()
                .filter_map(|v| v.perpendicular_irradiance(DVec3::ZERO))
                .map(|(w, e)| {
                    e.x * f64::from(
                        brdf::glossy_cos(glam::Vec3::ONE, roughness as f32, glam::Vec3::Z, w.as_vec3(), glam::Vec3::Z).x,
                    )
                })
                .sum();
            for side in [4, 8, 16] {
                let map = HemisphereMap::fill(&vals, (DVec3::ZERO, eye), side, |_| 1.0);
                let factor = lookup_factor(DVec3::ZERO, DVec3::Z, eye, roughness).unwrap();
                let n = cache_normal(DVec3::Z, DVec3::ZERO, eye);
                let reflected = map.under_lobe(n, roughness * roughness).x * factor;
                assert!(
                    (reflected / albedo - 1.0).abs() < 0.12,
                    "roughness {roughness} side {side}: {reflected} vs {albedo}"
                );
            }
        }
    }

    #[test]
    fn the_lookup_converges_to_the_brute_force_glossy_gather_as_maps_grow() {
        // A 32x32 floor of VALs; glossy receivers above it at grazing, frontal and tilted
        // views: the summed error falls from 4² to 16² to 64² maps (measured 21, 0.7, 0.03;
        // one case is luckier at 8² than at 16²), and at 64² every case is within 1%.
        let mut vals = Vec::new();
        for i in 0..32 {
            for j in 0..32 {
                vals.push(Val {
                    position: DVec3::new(i as f64 / 32.0 - 0.5, 0.0, j as f64 / 32.0 - 0.5),
                    normal_sum: DVec3::Y,
                    flux: DVec3::splat(0.001),
                    texels: 1.0,
                    area: 0.001,
                    ..Val::default()
                });
            }
        }
        let eye = DVec3::new(0.0, 0.3, 2.0);
        let receivers = [
            (DVec3::new(0.0, 0.5, 0.0), DVec3::NEG_Y),
            (DVec3::new(0.0, 0.3, -0.6), DVec3::Z),
            (DVec3::new(0.3, 0.4, 0.1), DVec3::new(-0.3, -1.0, 0.2).normalize()),
        ];
        let mut summed = [0.0; 3];
        for (x, n) in receivers {
            for roughness in [0.35, 0.6, 1.0] {
                let brute = gather(&vals, (x, n, eye), DVec3::ONE, roughness).x;
                let error = |side: u32| {
                    let map = HemisphereMap::fill(&vals, (x, eye), side, |_| 1.0);
                    let factor = lookup_factor(x, n, eye, roughness).unwrap();
                    let local_n = cache_normal(n, x, eye);
                    (map.under_lobe(local_n, roughness * roughness).x * factor / brute - 1.0).abs()
                };
                let errors = [4, 16, 64].map(error);
                assert!(errors[2] < 0.01, "{x} r {roughness}: {errors:?}");
                for (sum, e) in summed.iter_mut().zip(errors) {
                    *sum += e;
                }
            }
        }
        assert!(summed[0] > summed[1] && summed[1] > summed[2], "{summed:?}");
    }
}
