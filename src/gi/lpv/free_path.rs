//! The scene's mean free path between surfaces, the scale two-scale ILPV fits its far-field
//! lattice to: rays leave area-sampled surface points, cosine-distributed about either side of
//! the surface, and the mean distance to the next surface of those that hit one is taken (rays
//! that leave the scene are not counted). For a closed convex room this is the mean chord
//! length 4V/S (Cauchy): 2/3 of the edge of a cube.

use glam::Vec3;

use crate::reference::cpu::sample_cosine_hemisphere;
use crate::reference::rng::random_float;
use crate::scene::Mesh;
use crate::scene::bvh::Bvh;

/// Rays cast (a fixed sequence: the estimate is deterministic).
const RAYS: u32 = 4096;
const SEED: u32 = 0x000f_a2f1;

/// The mean free path, in scene units, of rays from the surfaces of `mesh`; None when no ray
/// hits a surface (an open, convex scene: a single plane or a lone box seen from outside).
pub fn mean_free_path(mesh: &Mesh) -> Option<f64> {
    let triangles = mesh.triangle_count();
    let mut cumulative = Vec::with_capacity(triangles);
    let mut total = 0.0f64;
    for t in 0..triangles {
        let [a, b, c] = mesh.triangle(t);
        total += f64::from(0.5 * (b - a).cross(c - a).length());
        cumulative.push(total);
    }
    if total <= 0.0 || !total.is_finite() {
        return None;
    }
    let bvh = Bvh::build(mesh);
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    // Rays start this far off their surface: a millionth of the scene, in any unit.
    let nudge = 1e-6 * (hi - lo).length();
    let (mut sum, mut hits) = (0.0f64, 0u32);
    for ray in 0..RAYS {
        let u = |dimension: u32| random_float(SEED, ray, 0, dimension);
        let target = f64::from(u(0)) * total;
        let t = cumulative.partition_point(|&c| c <= target).min(triangles - 1);
        let [a, b, c] = mesh.triangle(t);
        let (mut s, mut r) = (u(1), u(2));
        if s + r > 1.0 {
            (s, r) = (1.0 - s, 1.0 - r);
        }
        let point = a + s * (b - a) + r * (c - a);
        let mut normal = mesh.face_normal(t);
        if u(3) < 0.5 {
            normal = -normal;
        }
        let direction = sample_cosine_hemisphere(normal, u(4), u(5));
        let origin = point + normal * nudge;
        if let Some(hit) = bvh.intersect(origin, direction, 0.0, f32::INFINITY) {
            sum += f64::from(hit.t);
            hits += 1;
        }
    }
    (hits > 0).then(|| sum / f64::from(hits))
}

/// The unit cube's six faces, two triangles each.
#[cfg(test)]
fn unit_cube() -> Mesh {
    let mut mesh = Mesh::default();
    mesh.push_cuboid(Vec3::ZERO, Vec3::ONE, 0);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_cube_gives_cauchys_mean_chord() {
        // 4V/S = 4 / 6 for the unit cube; 4096 rays give about 1% noise.
        let Some(path) = mean_free_path(&unit_cube()) else {
            panic!("rays inside a closed cube hit its walls");
        };
        assert!((path - 2.0 / 3.0).abs() < 0.02, "mean free path {path}");
    }

    #[test]
    fn the_path_scales_with_the_scene() {
        let mut cube = unit_cube();
        for p in &mut cube.positions {
            *p *= 0.001;
        }
        let small = mean_free_path(&cube).unwrap_or(f64::NAN);
        let unit = mean_free_path(&unit_cube()).unwrap_or(f64::NAN);
        assert!((small / unit - 0.001).abs() < 1e-5, "{small} against {unit}");
    }

    #[test]
    fn a_lone_plane_has_no_free_path() {
        let mut cube = unit_cube();
        cube.indices.truncate(2);
        cube.materials.truncate(2);
        assert_eq!(mean_free_path(&cube), None);
    }
}
