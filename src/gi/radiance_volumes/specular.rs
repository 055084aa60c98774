//! Indirect specular from per-cache hemisphere maps (spec 001 §4.7), in f64: the map's
//! parameterisation, a cache's map filled from the VALs, its mips, and the apply pass's glossy
//! lookup. The GPU passes (light.comp fills, apply.comp looks up; shaders-glsl/gi/
//! radiance_volumes/specular.glsl) are tested against these.
//!
//! A cache's map covers the hemisphere of half vectors h around z = the direction from the cache
//! to the cascades' eye (the camera). A VAL seen along l sends its perpendicular irradiance E
//! to the texel holding h = normalize(l + z), as a density over the texel's solid angle: the
//! texel holds T(h) = Σ E / ΔΩ, the incoming light carried into the half-vector domain. The
//! glossy lobe of src/scene/brdf.rs then reflects toward the eye, for a surface of normal n,
//!
//!   L = specular · G1(n·v)² / (4 n·v) · ∫ T(h) D(h) dh ≈ specular · G1(n·v)² / (4 n·v) · T̄(n),
//!
//! T̄ the map box-filtered over the lobe's width (a mip level chosen from the roughness). The
//! approximations: D integrates to about 1 over the lobe (exact for narrow lobes), and the
//! shadowing term is taken at l = reflect(v, n).
//!
//! The parameterisation is the concentric square map of the Lambert equal-area disc: every
//! texel of a P×P map subtends exactly 2π/P² sr, so a 2×2 box average is a solid-angle average.

use glam::DVec3;

use super::cpu::Val;
use crate::scene::brdf;

/// Where unit `h` (h.z ≥ 0) falls in the unit square.
pub fn map(h: DVec3) -> (f64, f64) {
    let r = 0.5 * (1.0 - h.z.min(1.0)).max(0.0).sqrt();
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

/// Mip levels of a map of side `side` (down to one texel).
pub fn levels(side: u32) -> u32 {
    side.trailing_zeros() + 1
}

/// Texels of one cache's map, every level.
pub fn texels_per_cache(side: u32) -> u32 {
    (0..levels(side)).map(|l| (side >> l).pow(2)).sum()
}

/// Where level `level` starts in a cache's texels.
pub fn level_offset(side: u32, level: u32) -> u32 {
    (0..level).map(|l| (side >> l).pow(2)).sum()
}

/// One cache's hemisphere map, every level (level 0 first, rows of `side >> level` texels).
#[derive(Clone, Debug, PartialEq)]
pub struct HemisphereMap {
    pub side: u32,
    pub texels: Vec<DVec3>,
}

impl HemisphereMap {
    /// The map of a cache at `x` seen from `eye`, from every VAL (times `visibility(j)`),
    /// mips included.
    pub fn fill(
        vals: &[Val],
        (x, eye): (DVec3, DVec3),
        side: u32,
        mut visibility: impl FnMut(usize) -> f64,
    ) -> HemisphereMap {
        let mut map_texels = vec![DVec3::ZERO; texels_per_cache(side) as usize];
        let basis = frame((eye - x).normalize_or(DVec3::Z));
        let density = f64::from(side * side) / (2.0 * std::f64::consts::PI);
        for (j, val) in vals.iter().enumerate() {
            let Some((w, e)) = val.perpendicular_irradiance(x) else {
                continue;
            };
            if let Some(texel) = texel_of(local(w, basis), side) {
                map_texels[texel] += e * (visibility(j) * density);
            }
        }
        let mut map = HemisphereMap {
            side,
            texels: map_texels,
        };
        map.build_mips();
        map
    }

    /// Every level above 0 as the 2×2 mean of the one below.
    fn build_mips(&mut self) {
        for level in 1..levels(self.side) {
            let (s, from, to) = (
                (self.side >> level) as usize,
                level_offset(self.side, level - 1) as usize,
                level_offset(self.side, level) as usize,
            );
            for y in 0..s {
                for x in 0..s {
                    let child = |dx: usize, dy: usize| self.texels[from + (2 * y + dy) * 2 * s + 2 * x + dx];
                    self.texels[to + y * s + x] =
                        (child(0, 0) + child(1, 0) + child(0, 1) + child(1, 1)) * 0.25;
                }
            }
        }
    }

    /// The map at `(u, v)` filtered trilinearly at `lod` (bilinear within a level, clamped to
    /// the texel centres so no neighbouring tile is read, then linear between levels).
    pub fn sample(&self, (u, v): (f64, f64), lod: f64) -> DVec3 {
        let top = f64::from(levels(self.side) - 1);
        let lod = lod.clamp(0.0, top);
        let below = lod.floor();
        let f = lod - below;
        let at = |level: u32| {
            let s = self.side >> level;
            let first = level_offset(self.side, level) as usize;
            let max = f64::from(s - 1);
            let (x, y) = (
                (u * f64::from(s) - 0.5).clamp(0.0, max),
                (v * f64::from(s) - 0.5).clamp(0.0, max),
            );
            let (x0, y0) = (x.floor(), y.floor());
            let (fx, fy) = (x - x0, y - y0);
            let (x0, y0) = (x0 as usize, y0 as usize);
            let (x1, y1) = ((x0 + 1).min(s as usize - 1), (y0 + 1).min(s as usize - 1));
            let t = |x: usize, y: usize| self.texels[first + y * s as usize + x];
            (t(x0, y0) * (1.0 - fx) + t(x1, y0) * fx) * (1.0 - fy)
                + (t(x0, y1) * (1.0 - fx) + t(x1, y1) * fx) * fy
        };
        let lower = at(below as u32);
        if f > 0.0 {
            lower * (1.0 - f) + at(below as u32 + 1) * f
        } else {
            lower
        }
    }
}

/// The level-0 texel holding the half vector of light from local direction `l`; None for light
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

/// The mip level whose bilinear footprint is about as wide as the GGX lobe of `roughness` in a
/// map of `side`: near the map's centre a texel of level L spans 2√2 · 2^L / side radians of
/// half-vector angle, and half the lobe's mass lies within α of its axis; log2(side · α / 2)
/// returns uniform light 3% low at roughness 0.5 (the test below), a level coarser 8% low.
pub fn lod(side: u32, roughness: f64) -> f64 {
    let alpha = roughness * roughness;
    (f64::from(side) * alpha / 2.0)
        .log2()
        .clamp(0.0, f64::from(levels(side) - 1))
}

/// Where the lookup reads a map for a surface of normal `n` at `p` seen from `eye` (the frame
/// of the pixel, shared by its 8 corner caches), and the factor G1(n·v)² / (4 n·v) that turns
/// the filtered map into reflected radiance per unit specular reflectance; None where the
/// surface faces away from the eye.
pub fn lookup_at(p: DVec3, n: DVec3, eye: DVec3, roughness: f64) -> Option<((f64, f64), f64)> {
    let v = (eye - p).normalize_or(DVec3::Z);
    let n_v = n.dot(v);
    if n_v <= 0.0 {
        return None;
    }
    let n_local = local(n, frame(v));
    let a = roughness * roughness;
    let g1 = f64::from(brdf::smith_g1(n_v as f32, (a * a) as f32));
    Some((map(n_local), g1 * g1 / (4.0 * n_v)))
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
        let map = HemisphereMap::fill(&vals, (DVec3::ZERO, eye), 16, |_| 1.0);
        let ((u, v), factor) = lookup_at(DVec3::ZERO, DVec3::Z, eye, 0.5).unwrap();
        let reflected = map.sample((u, v), lod(16, 0.5)).x * factor;
        let a2 = 0.25f32 * 0.25;
        let g1 = f64::from(brdf::smith_g1(1.0, a2));
        assert!((reflected / (g1 * g1) - 1.0).abs() < 0.05, "{reflected}");
    }
}
