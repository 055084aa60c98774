//! The camera-centred cascaded grids of spec 001 §4.1: cascade i is a cube of side S_i = S_0·2^i
//! snapped to its own cell size h_i = S_i/N around the eye, with caches at the corners of its
//! N³ cells ((N+1)³ corners per cascade, so a cell's far corners always exist). A point belongs
//! to the smallest cascade whose unsnapped decision box (the cube around the eye, shrunk by 1.5
//! cells) holds it, blends into the next one within T cells of that box's faces, and to the
//! last cascade anywhere in its snapped grid; beyond that it gets no cached light.
//!
//! The shaders derive the boxes from the eye and the first cascade's side in their push
//! constants (shaders-glsl/gi/radiance_volumes/rv.glsl `rv_cascade`, `rv_select`, `rv_cell`);
//! this module mirrors them in the same f32 arithmetic, for the host and for tests.

use glam::Vec3;

/// Most cascades (spec 001 §5: 1-4).
pub const MAX_CASCADES: usize = 4;

/// Cells of margin between a decision box and its grid (spec 001 §4.1).
const DECISION_MARGIN: f32 = 1.5;

/// One cascade's boxes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    /// The snapped grid's minimum corner.
    pub lo: Vec3,
    pub cell: f32,
    /// The unsnapped decision box.
    pub decision_lo: Vec3,
    pub decision_hi: Vec3,
}

/// The cascades of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Cascades {
    /// The cascades' centre.
    pub eye: Vec3,
    /// Side of cascade 0.
    pub first_side: f32,
    /// Cells per side of every cascade.
    pub resolution: u32,
    /// Cells over which a cascade blends into the next (0: none).
    pub transition: f32,
    pub cascades: Vec<Cascade>,
}

/// Which cascade serves a point, and how far it blends into the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Selection {
    pub cascade: usize,
    /// Weight of cascade + 1 (0: this cascade alone).
    pub blend: f32,
}

impl Cascades {
    /// `count` cascades of `resolution`³ cells around `eye`, the first `first_side` wide, with
    /// transitions `transition` cells wide (0: none).
    pub fn around(
        eye: Vec3,
        count: usize,
        resolution: u32,
        first_side: f32,
        transition: f32,
    ) -> Cascades {
        let cascades = (0..count)
            .map(|i| {
                let side = first_side * (1u32 << i) as f32;
                let cell = side / resolution as f32;
                let half = 0.5 * side - DECISION_MARGIN * cell;
                Cascade {
                    lo: ((eye / cell + 0.5).floor() + 0.5) * cell - Vec3::splat(0.5 * side),
                    cell,
                    decision_lo: eye - Vec3::splat(half),
                    decision_hi: eye + Vec3::splat(half),
                }
            })
            .collect();
        Cascades {
            eye,
            first_side,
            resolution,
            transition,
            cascades,
        }
    }

    /// Corners (cache slots) of one cascade.
    pub fn corners_per_cascade(&self) -> usize {
        (self.resolution as usize + 1).pow(3)
    }

    /// The cascade serving `p`, or None beyond the last one's grid.
    pub fn select(&self, p: Vec3) -> Option<Selection> {
        let last = self.cascades.len() - 1;
        for (i, c) in self.cascades.iter().enumerate().take(last) {
            let (lo, hi) = (c.decision_lo, c.decision_hi);
            if p.cmpge(lo).all() && p.cmple(hi).all() {
                let blend = if self.transition > 0.0 {
                    let inside = (p - lo).min(hi - p).min_element();
                    (1.0 - inside / (c.cell * self.transition)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                return Some(Selection { cascade: i, blend });
            }
        }
        let c = &self.cascades[last];
        let hi = c.lo + Vec3::splat(c.cell * self.resolution as f32);
        (p.cmpge(c.lo).all() && p.cmple(hi).all()).then_some(Selection {
            cascade: last,
            blend: 0.0,
        })
    }

    /// The cell of cascade `i` holding `p` and the position within it.
    pub fn cell(&self, i: usize, p: Vec3) -> ([u32; 3], Vec3) {
        let c = &self.cascades[i];
        let u = (p - c.lo) / c.cell;
        let last = (self.resolution - 1) as f32;
        let g = u.floor().clamp(Vec3::ZERO, Vec3::splat(last));
        let f = (u - g).clamp(Vec3::ZERO, Vec3::ONE);
        ([g.x as u32, g.y as u32, g.z as u32], f)
    }

    /// Index of corner `corner` (of cascade `i`) in the address volume.
    pub fn corner_index(&self, i: usize, corner: [u32; 3]) -> usize {
        let side = self.resolution as usize + 1;
        i * self.corners_per_cascade()
            + corner[0] as usize
            + side * (corner[1] as usize + side * corner[2] as usize)
    }

    /// World position of corner `corner` of cascade `i`.
    pub fn corner_position(&self, i: usize, corner: [u32; 3]) -> Vec3 {
        let c = &self.cascades[i];
        c.lo + Vec3::new(corner[0] as f32, corner[1] as f32, corner[2] as f32) * c.cell
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decision_boxes_nest_and_keep_every_corner_inside_their_grid() {
        for eye in [
            Vec3::ZERO,
            Vec3::new(0.37, -1.91, 2.26),
            Vec3::new(-13.1, 4.06, 0.013),
        ] {
            let c = Cascades::around(eye, 3, 32, 4.0, 2.0);
            let mut rng = 0x2545_f491_u32;
            let mut next = || {
                rng ^= rng << 13;
                rng ^= rng >> 17;
                rng ^= rng << 5;
                rng as f32 / u32::MAX as f32
            };
            for _ in 0..20_000 {
                let p = eye + (Vec3::new(next(), next(), next()) - 0.5) * 18.0;
                let Some(s) = c.select(p) else {
                    continue;
                };
                let uses = if s.blend > 0.0 {
                    vec![s.cascade, s.cascade + 1]
                } else {
                    vec![s.cascade]
                };
                for i in uses {
                    assert!(i < 3);
                    let (g, f) = c.cell(i, p);
                    assert!(g.iter().all(|&g| g < 32), "{g:?}");
                    assert!(f.cmpge(Vec3::ZERO).all() && f.cmple(Vec3::ONE).all());
                    // The interpolated position is p: the cell really holds it.
                    let corner = c.corner_position(i, g) + f * c.cascades[i].cell;
                    assert!((corner - p).abs().max_element() < 1e-4, "{corner} vs {p}");
                }
            }
        }
    }

    #[test]
    fn points_near_a_decision_box_face_blend_into_the_next_cascade() {
        let c = Cascades::around(Vec3::ZERO, 2, 32, 4.0, 2.0);
        let h = c.cascades[0].cell;
        let face = c.cascades[0].decision_hi.x;
        let deep = c.select(Vec3::new(face - 3.0 * h, 0.0, 0.0)).unwrap();
        assert_eq!((deep.cascade, deep.blend), (0, 0.0));
        let half = c.select(Vec3::new(face - h, 0.0, 0.0)).unwrap();
        assert_eq!(half.cascade, 0);
        assert!((half.blend - 0.5).abs() < 1e-4, "{}", half.blend);
        let outside = c.select(Vec3::new(face + 0.01, 0.0, 0.0)).unwrap();
        assert_eq!((outside.cascade, outside.blend), (1, 0.0));
        assert_eq!(c.select(Vec3::new(5.0, 0.0, 0.0)), None);
    }
}
