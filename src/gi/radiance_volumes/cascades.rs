//! The camera-centred cascaded grids of spec 001 §4.1: cascade i is a cube of side S_i = S_0·2^i
//! snapped to its own cell size h_i = S_i/N around the eye, with caches at the corners of its
//! N³ cells ((N+1)³ corners per cascade, so a cell's far corners always exist). A point belongs
//! to the smallest cascade whose unsnapped decision box (the cube around the eye, shrunk by 1.5
//! cells) holds it, blends into the next one within T cells of that box's faces, and to the
//! last cascade anywhere in its snapped grid; beyond that it gets no cached light.
//!
//! The boxes are computed here, in f32, once per frame, and handed to the shaders
//! (shaders-glsl/gi/radiance_volumes/rv.glsl selects with them); `select` mirrors the shader for
//! tests.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Most cascades (spec 001 §5: 1-4).
pub const MAX_CASCADES: usize = 4;

/// Cells of margin between a decision box and its grid (spec 001 §4.1).
const DECISION_MARGIN: f32 = 1.5;

/// One cascade as the shaders read it (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCascade {
    /// xyz: the snapped grid's minimum corner, w: the cell size h.
    pub min_cell: [f32; 4],
    /// xyz: the decision box's minimum, w: the transition width T in cells.
    pub decision_min: [f32; 4],
    /// xyz: the decision box's maximum, w: unused.
    pub decision_max: [f32; 4],
}

/// The cascades of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Cascades {
    /// Cells per side of every cascade.
    pub resolution: u32,
    pub cascades: Vec<GpuCascade>,
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
                let min = (eye / cell).round() * cell - Vec3::splat(0.5 * side);
                let half = 0.5 * side - DECISION_MARGIN * cell;
                let (d_min, d_max) = (eye - Vec3::splat(half), eye + Vec3::splat(half));
                GpuCascade {
                    min_cell: min.extend(cell).to_array(),
                    decision_min: d_min.extend(transition).to_array(),
                    decision_max: d_max.extend(0.0).to_array(),
                }
            })
            .collect();
        Cascades {
            resolution,
            cascades,
        }
    }

    /// Corners (cache slots) of one cascade.
    pub fn corners_per_cascade(&self) -> usize {
        (self.resolution as usize + 1).pow(3)
    }

    /// The cascade serving `p`, or None beyond the last one's grid (mirrors rv.glsl's
    /// `rv_select`).
    pub fn select(&self, p: Vec3) -> Option<Selection> {
        let last = self.cascades.len() - 1;
        for (i, c) in self.cascades.iter().enumerate().take(last) {
            let (lo, hi) = (
                Vec3::from_slice(&c.decision_min[..3]),
                Vec3::from_slice(&c.decision_max[..3]),
            );
            if p.cmpge(lo).all() && p.cmple(hi).all() {
                let transition = c.decision_min[3];
                let blend = if transition > 0.0 {
                    let inside = (p - lo).min(hi - p).min_element();
                    (1.0 - inside / (c.min_cell[3] * transition)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                return Some(Selection { cascade: i, blend });
            }
        }
        let c = &self.cascades[last];
        let min = Vec3::from_slice(&c.min_cell[..3]);
        let max = min + Vec3::splat(c.min_cell[3] * self.resolution as f32);
        (p.cmpge(min).all() && p.cmple(max).all()).then_some(Selection {
            cascade: last,
            blend: 0.0,
        })
    }

    /// The cell of cascade `i` holding `p` and the position within it (mirrors `rv_cell`).
    pub fn cell(&self, i: usize, p: Vec3) -> ([u32; 3], Vec3) {
        let c = &self.cascades[i];
        let u = (p - Vec3::from_slice(&c.min_cell[..3])) / c.min_cell[3];
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
        Vec3::from_slice(&c.min_cell[..3])
            + Vec3::new(corner[0] as f32, corner[1] as f32, corner[2] as f32) * c.min_cell[3]
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
                    let corner = c.corner_position(i, g) + f * c.cascades[i].min_cell[3];
                    assert!((corner - p).abs().max_element() < 1e-4, "{corner} vs {p}");
                }
            }
        }
    }

    #[test]
    fn points_near_a_decision_box_face_blend_into_the_next_cascade() {
        let c = Cascades::around(Vec3::ZERO, 2, 32, 4.0, 2.0);
        let h = c.cascades[0].min_cell[3];
        let face = c.cascades[0].decision_max[0];
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
