//! The f64 reference of the method's core, which the GPU passes are tested against: a record's
//! reduction from its hemisphere (E, gradients, harmonic mean distance), Ward's weight and the
//! gradient extrapolation of a record at a point, the brute-force gather the splat must equal,
//! and the conservative screen bounds of a record's sphere of influence. Also the hemisphere
//! itself sampled by a caller's ray cast, the surface a hemisphere texel sees, and a
//! brute-force integral over the whole hemisphere for the gradient and Table 8.1 tests.

use glam::{DMat4, DVec3, DVec4};

use super::bindings as ids;
use super::tables::{self, Tables};
use crate::reference::rng::random_float;
use crate::scene::Scene;
use crate::scene::bvh::Bvh;

/// Smallest inverse weight (spec 003 Alg. 3 EPSILON): the weight is infinite at the record.
pub const MIN_INVERSE_WEIGHT: f64 = ids::IC_MIN_INVERSE_WEIGHT as f64;
/// A record lights a point only if the point is not behind it by more than this fraction of
/// its R (Ward's "in front" test, measured along the mean of the two normals).
pub const BEHIND_TOLERANCE: f64 = ids::IC_BEHIND_TOLERANCE as f64;

/// The tangent and bitangent around unit `n` (Duff et al. 2017; GLSL `orthonormal_basis`).
pub fn basis(n: DVec3) -> (DVec3, DVec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let c = n.x * n.y * a;
    (
        DVec3::new(1.0 + s * n.x * n.x * a, s * c, -s * n.x),
        DVec3::new(c, s + n.y * n.y * a, -n.y),
    )
}

/// One irradiance record, world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    pub position: DVec3,
    pub normal: DVec3,
    /// Irradiance per channel (W/m²).
    pub irradiance: [f64; 3],
    /// ∇_r E per channel.
    pub rotation: [DVec3; 3],
    /// ∇_t E per channel.
    pub translation: [DVec3; 3],
    /// Harmonic mean distance R (after any clamp).
    pub harmonic: f64,
}

/// A record's hemisphere: per texel (row-major, as the tables) the radiance arriving and the
/// distance to what it came from (None: nothing hit).
pub struct Hemisphere {
    pub radiance: Vec<[f64; 3]>,
    pub distance: Vec<Option<f64>>,
}

/// The record at `position`, `normal` from its hemisphere (no clamp on R). A hemisphere that
/// hits nothing gets R = ∞.
pub fn reduce(tables: &Tables, hemisphere: &Hemisphere, position: DVec3, normal: DVec3) -> Record {
    let r = tables.resolution;
    let mut e = [0.0; 3];
    let mut rot = [[0.0; 2]; 3];
    let mut trans = [[0.0; 2]; 3];
    let (mut weight_sum, mut weight_over_distance) = (0.0, 0.0);
    let far = |d: Option<f64>| d.unwrap_or(f64::INFINITY);
    for j in 0..r {
        for i in 0..r {
            let t = j * r + i;
            let l = hemisphere.radiance[t];
            let w = tables.weight[t];
            weight_sum += w;
            if let Some(d) = hemisphere.distance[t] {
                weight_over_distance += w / d;
            }
            let d = far(hemisphere.distance[t]);
            let mut neighbours = Vec::with_capacity(2);
            if i + 1 < r {
                neighbours.push((t + 1, tables.right[t]));
            }
            if j + 1 < r {
                neighbours.push((t + r, tables.down[t]));
            }
            for c in 0..3 {
                e[c] += w * l[c];
                rot[c][0] += tables.rotation[t][0] * l[c];
                rot[c][1] += tables.rotation[t][1] * l[c];
            }
            for (next, g) in neighbours {
                let nearest = d.min(far(hemisphere.distance[next]));
                if !nearest.is_finite() {
                    continue;
                }
                for c in 0..3 {
                    let step = (hemisphere.radiance[next][c] - l[c]) / nearest;
                    trans[c][0] += g[0] * step;
                    trans[c][1] += g[1] * step;
                }
            }
        }
    }
    let (tangent, bitangent) = basis(normal);
    let world = |v: [f64; 2]| tangent * v[0] + bitangent * v[1];
    Record {
        position,
        normal,
        irradiance: e,
        rotation: rot.map(world),
        translation: trans.map(world),
        harmonic: if weight_over_distance > 0.0 {
            weight_sum / weight_over_distance
        } else {
            f64::INFINITY
        },
    }
}

/// R limited and clamped as the GPU reduction does: to E/|∇_t E| per channel, then so the zone
/// a·R spans `zone_pixels` view pixels of world size `footprint`; a record widened by the clamp
/// has its translation gradient scaled down by as much (Křivánek et al. 2006).
pub fn limit_radius(record: &mut Record, footprint: f64, accuracy: f64, zone_pixels: [f64; 2]) {
    let mut limited = record.harmonic;
    for c in 0..3 {
        let slope = record.translation[c].length();
        if slope > 0.0 && record.irradiance[c] > 0.0 {
            limited = limited.min(record.irradiance[c] / slope);
        }
    }
    let radius = limited.clamp(
        zone_pixels[0] * footprint / accuracy,
        zone_pixels[1] * footprint / accuracy,
    );
    if radius > limited {
        for t in &mut record.translation {
            *t *= limited / radius;
        }
    }
    record.harmonic = radius;
}

/// Sample the hemisphere of a record at `position`, `normal` through the centre of every
/// texel of the tables' plane; `trace(origin, direction)` gives the radiance arriving from
/// `direction` and the distance to its source, or None.
pub fn sample_hemisphere(
    resolution: usize,
    position: DVec3,
    normal: DVec3,
    trace: &dyn Fn(DVec3, DVec3) -> Option<([f64; 3], f64)>,
) -> Hemisphere {
    let (tangent, bitangent) = basis(normal);
    let mut radiance = Vec::with_capacity(resolution * resolution);
    let mut distance = Vec::with_capacity(resolution * resolution);
    for j in 0..resolution {
        for i in 0..resolution {
            let d = tables::texel_direction(i, j, resolution);
            let dir = tangent * d.x + bitangent * d.y + normal * d.z;
            let hit = trace(position, dir);
            radiance.push(hit.map_or([0.0; 3], |h| h.0));
            distance.push(hit.map(|h| h.1));
        }
    }
    Hemisphere { radiance, distance }
}

/// The surface a hemisphere texel sees, as hemisphere.frag shades it.
pub struct VisibleSurface {
    pub position: DVec3,
    /// The shading normal, turned to face the ray's origin (the face normal where it leans
    /// the other way).
    pub normal: DVec3,
    /// The face normal, facing the ray's origin.
    pub face: DVec3,
    pub albedo: DVec3,
    pub distance: f64,
}

/// The closest surface along a ray past `t_min` through the scene's BVH.
pub fn visible_surface(
    scene: &Scene,
    bvh: &Bvh,
    origin: DVec3,
    dir: DVec3,
    t_min: f64,
) -> Option<VisibleSurface> {
    let mesh = &scene.mesh;
    let hit = bvh.intersect(origin.as_vec3(), dir.as_vec3(), t_min as f32, 1e30)?;
    let face = mesh.face_normal(hit.triangle).as_dvec3();
    let facing = if face.dot(dir) <= 0.0 { 1.0 } else { -1.0 };
    let face = face * facing;
    let shading = mesh.shading_normal(hit.triangle, hit.uv).as_dvec3() * facing;
    let distance = f64::from(hit.t);
    Some(VisibleSurface {
        position: origin + dir * distance,
        normal: if shading.dot(face) > 0.0 { shading } else { face },
        face,
        albedo: scene.albedo(hit.triangle, hit.uv).as_dvec3(),
        distance,
    })
}

/// E at `position`, `normal` over `n`×`n` cells of the cosine-weighted square, one direction
/// per cell of weight π/n²: at each cell's centre (a midpoint rule, smooth in `position` for
/// finite differences), or drawn at random in it with `jitter`'s seed (stratified Monte Carlo):
/// the brute-force hemisphere integral.
pub fn integrate_hemisphere(
    n: usize,
    jitter: Option<u32>,
    position: DVec3,
    normal: DVec3,
    trace: &dyn Fn(DVec3, DVec3) -> Option<([f64; 3], f64)>,
) -> [f64; 3] {
    let (tangent, bitangent) = basis(normal);
    let mut e = [0.0; 3];
    for a in 0..n {
        for b in 0..n {
            let (j1, j2) = match jitter {
                None => (0.5, 0.5),
                Some(seed) => {
                    let cell = (a * n + b) as u32;
                    let u = |d| f64::from(random_float(seed, cell, 0, d));
                    (u(0), u(1))
                }
            };
            let u1 = (a as f64 + j1) / n as f64;
            let u2 = (b as f64 + j2) / n as f64;
            let r = u1.sqrt();
            let phi = std::f64::consts::TAU * u2;
            let dir = tangent * (r * phi.cos())
                + bitangent * (r * phi.sin())
                + normal * (1.0 - u1).max(0.0).sqrt();
            if let Some((l, _)) = trace(position, dir) {
                for c in 0..3 {
                    e[c] += l[c];
                }
            }
        }
    }
    e.map(|v| v * std::f64::consts::PI / (n * n) as f64)
}

/// How records weigh points (spec 003 §2–§4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weighting {
    /// Ward's a: a record reaches at most a·R.
    pub accuracy: f64,
    /// w − 1/a (§8.2) rather than w: contributions fade to 0 at the edge of the zone.
    pub smooth: bool,
    /// κ in √(κ(1 − n·n_k)): 1 as Eq. 8.2, 0.2 as Alg. 3.
    pub normal_factor: f64,
    /// Largest weight (the accumulated sums stay finite).
    pub max_weight: f64,
}

impl Weighting {
    /// Record `k`'s weight at point `p` with normal `n`, None where it does not contribute.
    pub fn weight(&self, k: &Record, p: DVec3, n: DVec3) -> Option<f64> {
        let a = self.accuracy;
        let diff = p - k.position;
        let e1 = diff.length_squared() / (k.harmonic * k.harmonic);
        // 1 − n·n_k as |n − n_k|²/2 (unit vectors): no cancellation where the normals agree.
        let e2 = self.normal_factor * 0.5 * (n - k.normal).length_squared();
        if e1 + e2 > a * a {
            return None;
        }
        let inverse = (e1.sqrt() + e2.sqrt()).max(MIN_INVERSE_WEIGHT);
        if inverse > a || diff.dot(n + k.normal) < -2.0 * BEHIND_TOLERANCE * k.harmonic {
            return None;
        }
        let w = 1.0 / inverse - if self.smooth { 1.0 / a } else { 0.0 };
        Some(w.min(self.max_weight))
    }
}

/// Record `k`'s irradiance extrapolated to `p`, `n` by its gradients (Alg. 4), never negative.
pub fn extrapolate(k: &Record, p: DVec3, n: DVec3) -> [f64; 3] {
    let turn = k.normal.cross(n);
    let shift = p - k.position;
    std::array::from_fn(|c| {
        (k.irradiance[c] + turn.dot(k.rotation[c]) + shift.dot(k.translation[c])).max(0.0)
    })
}

/// Σ_k w_k E′_k and Σ_k w_k at `p`, `n` over every record: what the splat accumulates.
pub fn gather(records: &[Record], weighting: &Weighting, p: DVec3, n: DVec3) -> ([f64; 3], f64) {
    let mut sum = [0.0; 3];
    let mut weights = 0.0;
    for k in records {
        if let Some(w) = weighting.weight(k, p, n) {
            let e = extrapolate(k, p, n);
            for c in 0..3 {
                sum[c] += w * e[c];
            }
            weights += w;
        }
    }
    (sum, weights)
}

/// Where a sphere lands on screen: a rectangle in normalised device coordinates, or the whole
/// screen when the sphere reaches behind the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplatBounds {
    Rect { min: [f64; 2], max: [f64; 2] },
    FullScreen,
}

/// Smallest clip w a corner may have for its projection to count (else: the whole screen).
pub const MIN_CLIP_W: f64 = ids::IC_MIN_CLIP_W as f64;

/// Conservative screen bounds of the sphere (centre, radius) under `view_projection`: the
/// projections of its bounding box's 8 corners (a box holds the sphere, and its projection the
/// sphere's, as long as every corner is in front of the eye).
pub fn splat_bounds(view_projection: &DMat4, centre: DVec3, radius: f64) -> SplatBounds {
    let mut min = [f64::INFINITY; 2];
    let mut max = [f64::NEG_INFINITY; 2];
    for corner in 0..8 {
        let sign = |bit: usize| if corner & bit != 0 { 1.0 } else { -1.0 };
        let p = centre + DVec3::new(sign(1), sign(2), sign(4)) * radius;
        let clip = *view_projection * DVec4::new(p.x, p.y, p.z, 1.0);
        if clip.w <= MIN_CLIP_W {
            return SplatBounds::FullScreen;
        }
        for axis in 0..2 {
            let ndc = clip[axis] / clip.w;
            min[axis] = min[axis].min(ndc);
            max[axis] = max[axis].max(ndc);
        }
    }
    SplatBounds::Rect { min, max }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gi::irradiance_cache::tables::Coverage;

    #[test]
    fn the_basis_is_orthonormal_and_right_handed() {
        for n in [DVec3::Z, -DVec3::Z, DVec3::X, DVec3::new(0.3, -0.8, 0.1).normalize()] {
            let (t, b) = basis(n);
            assert!((t.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
            assert!(t.dot(b).abs() < 1e-12 && t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12);
            assert!((t.cross(b) - n).length() < 1e-12, "{n}");
        }
    }

    /// Spec 003 §17: a constant environment gives E = πL with border stretching.
    #[test]
    fn a_constant_sky_gives_pi_l_and_no_gradient() {
        let tables = Tables::new(64, Coverage::Stretch);
        let sky = |_: DVec3, _: DVec3| Some(([2.0, 1.0, 0.5], 7.0));
        let n = DVec3::new(0.2, 0.9, -0.1).normalize();
        let h = sample_hemisphere(64, DVec3::ONE, n, &sky);
        let k = reduce(&tables, &h, DVec3::ONE, n);
        for (c, l) in [2.0, 1.0, 0.5].into_iter().enumerate() {
            assert!((k.irradiance[c] - std::f64::consts::PI * l).abs() < 1e-9);
            assert!(k.rotation[c].length() < 1e-9 && k.translation[c].length() < 1e-9);
        }
        assert!((k.harmonic - 7.0).abs() < 1e-9);
    }

    fn record(position: DVec3, normal: DVec3, harmonic: f64) -> Record {
        Record {
            position,
            normal,
            irradiance: [1.0, 2.0, 3.0],
            rotation: [DVec3::ZERO; 3],
            translation: [DVec3::X * 0.1, DVec3::Y * 0.2, DVec3::Z * 0.3],
            harmonic,
        }
    }

    #[test]
    fn weights_reach_a_r_at_most_and_fade_to_zero_there_when_smooth() {
        let weighting = Weighting {
            accuracy: 0.5,
            smooth: true,
            normal_factor: 1.0,
            max_weight: 1e4,
        };
        let k = record(DVec3::ZERO, DVec3::Z, 2.0);
        // Zone radius a·R = 1.
        assert!(weighting.weight(&k, DVec3::X * 1.01, DVec3::Z).is_none());
        let edge = weighting.weight(&k, DVec3::X * 0.999, DVec3::Z).unwrap();
        assert!(edge < 0.01, "{edge}");
        let at_record = 1.0 / MIN_INVERSE_WEIGHT - 1.0 / 0.5;
        let w = weighting.weight(&k, DVec3::ZERO, DVec3::Z).unwrap();
        assert!((w - at_record).abs() < 1e-9, "{w}");
        // Behind the record (below its plane, facing the same way) it gives nothing.
        assert!(weighting.weight(&k, DVec3::new(0.05, 0.0, -0.3), DVec3::Z).is_none());
        // A turned normal weighs less.
        let turned = DVec3::new(0.3, 0.0, 1.0).normalize();
        let straight = weighting.weight(&k, DVec3::X * 0.2, DVec3::Z).unwrap();
        assert!(weighting.weight(&k, DVec3::X * 0.2, turned).unwrap() < straight);
    }

    #[test]
    fn extrapolation_adds_the_gradients_and_never_goes_negative() {
        let mut k = record(DVec3::ZERO, DVec3::Z, 1.0);
        let e = extrapolate(&k, DVec3::new(1.0, 1.0, 0.0), DVec3::Z);
        assert!((e[0] - 1.1).abs() < 1e-12 && (e[1] - 2.2).abs() < 1e-12 && e[2] == 3.0);
        k.translation[0] = DVec3::X * -10.0;
        assert_eq!(extrapolate(&k, DVec3::X, DVec3::Z)[0], 0.0);
    }

    #[test]
    fn splat_bounds_hold_every_visible_point_of_the_sphere() {
        // A simple pseudo-random sequence keeps the test deterministic.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut full = 0;
        for _ in 0..400 {
            let eye = DVec3::new(next(), next(), next()) * 4.0 - 2.0;
            let target = DVec3::new(next(), next(), next()) * 2.0 - 1.0;
            let camera = crate::scene::Camera {
                position: eye.as_vec3(),
                target: target.as_vec3(),
                up: glam::Vec3::Y,
                vfov_deg: (20.0 + next() * 100.0) as f32,
            };
            let aspect = (0.5 + next()) as f32;
            let vp = (camera.projection(aspect, 0.05, 50.0) * camera.view()).as_dmat4();
            let centre = DVec3::new(next(), next(), next()) * 6.0 - 3.0;
            let radius = 0.01 + next() * 1.5;
            let bounds = splat_bounds(&vp, centre, radius);
            let SplatBounds::Rect { min, max } = bounds else {
                full += 1;
                continue;
            };
            for _ in 0..200 {
                let dir = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize_or_zero();
                let p = centre + dir * radius * next().cbrt();
                let clip = vp * p.extend(1.0);
                if clip.w <= 0.0 {
                    continue;
                }
                for axis in 0..2 {
                    let ndc = clip[axis] / clip.w;
                    assert!(ndc >= min[axis] - 1e-9 && ndc <= max[axis] + 1e-9);
                }
            }
        }
        assert!(full < 400, "every sphere reached behind the eye");
    }
}
