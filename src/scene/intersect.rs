//! Ray-triangle intersection on the CPU (Möller–Trumbore), for tests and host-side estimators.

use glam::Vec3;

use super::Mesh;

/// The closest hit of a ray: distance along the (unit) direction and the triangle index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub triangle: usize,
    /// Barycentric coordinates of the hit for corners 1 and 2.
    pub uv: (f32, f32),
}

/// Distance along `dir` to triangle `[a, b, c]`, if hit in `(t_min, t_max)`.
pub fn intersect_triangle(
    origin: Vec3,
    dir: Vec3,
    [a, b, c]: [Vec3; 3],
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    intersect_edges(origin, dir, (a, b - a, c - a), t_min, t_max)
}

/// As [`intersect_triangle`] for a triangle given as its first corner and the edges to the
/// other two (`(a, b - a, c - a)`, the same values, so the same result).
#[inline]
pub fn intersect_edges(
    origin: Vec3,
    dir: Vec3,
    (a, e1, e2): (Vec3, Vec3, Vec3),
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > t_min && t < t_max).then_some((t, u, v))
}

impl Mesh {
    /// The closest triangle a ray hits in `(t_min, t_max)`, by testing every triangle.
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for t in 0..self.triangle_count() {
            let limit = best.map_or(t_max, |b| b.t);
            if let Some((dist, u, v)) =
                intersect_triangle(origin, dir, self.triangle(t), t_min, limit)
            {
                best = Some(Hit {
                    t: dist,
                    triangle: t,
                    uv: (u, v),
                });
            }
        }
        best
    }

    /// True when nothing blocks the segment from `from` to `to` (ends excluded by `epsilon`).
    pub fn visible(&self, from: Vec3, to: Vec3, epsilon: f32) -> bool {
        let d = to - from;
        let length = d.length();
        if length <= 2.0 * epsilon {
            return true;
        }
        self.intersect(from, d / length, epsilon, length - epsilon)
            .is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_and_misses_a_triangle() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let hit =
            intersect_triangle(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z, tri, 0.0, 10.0).unwrap();
        assert!((hit.0 - 1.0).abs() < 1e-6);
        assert!(
            intersect_triangle(Vec3::new(0.8, 0.8, 1.0), Vec3::NEG_Z, tri, 0.0, 10.0).is_none()
        );
        assert!(intersect_triangle(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, tri, 0.0, 10.0).is_none());
    }
}
