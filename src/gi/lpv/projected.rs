//! The projected-area blocking model of the geometry lattice ([`super::geometry`]): per cell
//! the area-weighted normal tensor M = Σ w N Nᵀ, the axis moments S = Σ w |N| and the outward
//! moment V = Σ A N_out of the surfaces that block one way only, in three SH-sized words:
//! (Mxx, Myy, Mzz, Mxy), (Mxz, Myz, Vx, Vy), (Vz, Sx, Sy, Sz). A surface that blocks both ways
//! counts twice in M and S (w = 2A), a one-way surface once (w = A).
//!
//! The transfer to the neighbour at offset o (in cells) is blocked by
//! ½ (P(o) + V·o), with P(o) = min(√(tr M · oᵀMo), S·|o|) ≈ Σ w |N·o|. Both terms of the min are
//! upper bounds of Σ w |N·o| (Cauchy–Schwarz; the triangle inequality), exact for a cell of
//! parallel surfaces and for one of axis-aligned surfaces respectively. So a cell of one plane
//! of area density A blocks A·|N·o| both ways, or A·max(0, N_out·o) one way: the area projected
//! on the direction of travel times the distance |o| travelled, i.e. the expected number of
//! crossings in the step. A wall filling its cells blocks every transfer that crosses it (face,
//! edge or corner) fully, and nothing that runs along it; a one-way wall only what leaves
//! through it. shaders-glsl/gi/lpv/blocking.glsl is the same in f32.

use glam::{DVec3, DVec4};

/// SH-sized words per cell.
pub const WORDS: usize = 3;

/// The words a surface of unit area density adds: `outward` is `Some(±normal)` for a surface
/// that blocks only light travelling along it, `None` for one that blocks both ways.
pub fn surface_words(normal: DVec3, outward: Option<DVec3>) -> [DVec4; WORDS] {
    let n = normal;
    let (w, v) = match outward {
        Some(out) => (1.0, out),
        None => (2.0, DVec3::ZERO),
    };
    let a = n.abs() * w;
    [
        DVec4::new(n.x * n.x, n.y * n.y, n.z * n.z, n.x * n.y) * w,
        DVec4::new(n.x * n.z * w, n.y * n.z * w, v.x, v.y),
        DVec4::new(v.z, a.x, a.y, a.z),
    ]
}

/// How much of the transfer to the neighbour at `offset` the cell `words` block, before the
/// step clamps the result to [0, 1].
pub fn blocking(words: [DVec4; WORDS], offset: DVec3) -> f64 {
    let [m, mv, vs] = words;
    let o = offset;
    let trace = m.x + m.y + m.z;
    let along = o.x * o.x * m.x
        + o.y * o.y * m.y
        + o.z * o.z * m.z
        + 2.0 * (o.x * o.y * m.w + o.x * o.z * mv.x + o.y * o.z * mv.y);
    let tensor = (trace * along).max(0.0).sqrt();
    let axes = vs.y * o.x.abs() + vs.z * o.y.abs() + vs.w * o.z.abs();
    let outward = DVec3::new(mv.z, mv.w, vs.x);
    0.5 * (tensor.min(axes) + outward.dot(o))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum(surfaces: &[(DVec3, Option<DVec3>)]) -> [DVec4; WORDS] {
        let mut words = [DVec4::ZERO; WORDS];
        for &(n, out) in surfaces {
            for (w, add) in words.iter_mut().zip(surface_words(n, out)) {
                *w += add;
            }
        }
        words
    }

    #[test]
    fn a_two_way_plane_blocks_its_projected_area_times_the_distance() {
        let wall = sum(&[(DVec3::X, None)]);
        for o in [DVec3::X, -DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::new(-1.0, 1.0, -1.0)] {
            assert!((blocking(wall, o) - 1.0).abs() < 1e-12, "{o}");
        }
        for o in [DVec3::Y, DVec3::Z, DVec3::new(0.0, 1.0, -1.0)] {
            assert!(blocking(wall, o).abs() < 1e-12, "{o}");
        }
        // Tilted: the tensor term is exact, the axis term only bounds it.
        let n = DVec3::new(1.0, 1.0, 0.0).normalize();
        let tilted = sum(&[(n, None)]);
        assert!(blocking(tilted, DVec3::new(1.0, -1.0, 0.0)).abs() < 1e-12);
        assert!((blocking(tilted, DVec3::X) - n.x).abs() < 1e-12);
    }

    #[test]
    fn a_one_way_plane_blocks_only_what_leaves_through_it() {
        let floor = sum(&[(DVec3::Y, Some(-DVec3::Y))]);
        assert!((blocking(floor, -DVec3::Y) - 1.0).abs() < 1e-12);
        assert!((blocking(floor, DVec3::new(1.0, -1.0, 1.0)) - 1.0).abs() < 1e-12);
        for o in [DVec3::Y, DVec3::X, DVec3::new(1.0, 1.0, 0.0)] {
            assert!(blocking(floor, o).abs() < 1e-12, "{o}");
        }
    }

    #[test]
    fn a_room_corner_lets_light_into_the_room() {
        // Floor and wall of a room's corner, each one-way toward the outside (-y, -x): the
        // axis term keeps the tensor's Cauchy–Schwarz excess (√2 for travel along x) out.
        let corner = sum(&[(DVec3::Y, Some(-DVec3::Y)), (DVec3::X, Some(-DVec3::X))]);
        for o in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 1.0, 1.0)] {
            assert!(blocking(corner, o).abs() < 1e-12, "{o}: {}", blocking(corner, o));
        }
        assert!((blocking(corner, -DVec3::X) - 1.0).abs() < 1e-12);
        assert!(blocking(corner, DVec3::new(-1.0, -1.0, 0.0)) >= 1.0);
    }
}
