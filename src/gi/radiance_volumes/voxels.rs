//! The binary voxelisation the indirect shadows are cone-traced through (spec 001 §4.6), in
//! f64: the cube around the scene, the voxels a triangle marks, the occupancy mip chain, its
//! quadrilinear sampling and the cone march. shaders-glsl/gi/radiance_volumes/voxelize.comp and
//! voxel.glsl mirror these; the tests hold them to each other.

use glam::{DVec3, Vec3};

use super::cpu::Val;

/// The cube of voxels around the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelGrid {
    /// The cube's minimum corner.
    pub min: Vec3,
    /// A voxel's side.
    pub voxel: f32,
    /// Voxels per side (a power of two).
    pub resolution: u32,
}

/// First sample of a cone, in voxels from its apex (spec 001 §4.6: clear of the surface the
/// cache serves).
pub const CONE_START: f64 = 2.0;
/// Most samples of one cone (the public code: 32). On lavapipe, cones of more than about 16
/// samples leave some caches of the lighting pass unwritten (they read back 0 even with the
/// visibility forced to 1; the f64 mirror test caught it at `--shadow-lod 0` with 64² VALs,
/// and its cause is not yet found), so the march stops at 16.
pub const CONE_STEPS: u32 = 16;

impl VoxelGrid {
    /// The cube around `[lo, hi]`, grown by a thousandth of its side so no surface lies on its
    /// boundary.
    pub fn fit(lo: Vec3, hi: Vec3, resolution: u32) -> VoxelGrid {
        let side = (hi - lo).max_element().max(1e-6) * 1.001;
        let centre = 0.5 * (lo + hi);
        VoxelGrid {
            min: centre - Vec3::splat(0.5 * side),
            voxel: side / resolution as f32,
            resolution,
        }
    }

    /// Levels of the mip chain, down to one voxel.
    pub fn levels(&self) -> u32 {
        self.resolution.trailing_zeros() + 1
    }

    /// Side of level `level`.
    pub fn side(&self, level: u32) -> usize {
        (self.resolution >> level) as usize
    }

    /// First voxel of level `level` in the chain.
    pub fn offset(&self, level: u32) -> usize {
        (0..level).map(|l| self.side(l).pow(3)).sum()
    }

    /// Voxels of every level.
    pub fn total(&self) -> usize {
        self.offset(self.levels())
    }

    /// Index of voxel `v` of level 0.
    pub fn index(&self, v: [usize; 3]) -> usize {
        let n = self.resolution as usize;
        v[0] + n * (v[1] + n * v[2])
    }

    /// `p` in level-0 voxel units.
    pub fn to_voxels(&self, p: DVec3) -> DVec3 {
        (p - self.min.as_dvec3()) / f64::from(self.voxel)
    }
}

/// The voxels triangle `t` (world space) marks: every voxel its surface touches, found column by
/// column along its dominant axis (the 2-D square of a column overlaps the projected triangle,
/// and the voxels between the plane's lowest and highest depth over that square, within the
/// triangle's own depth range). Degenerate triangles mark nothing.
pub fn voxelize_triangle(grid: &VoxelGrid, t: [DVec3; 3]) -> Vec<[usize; 3]> {
    let v = t.map(|p| grid.to_voxels(p));
    let normal = (v[1] - v[0]).cross(v[2] - v[0]);
    let a = normal.abs();
    if a.max_element() == 0.0 {
        return Vec::new();
    }
    // Dominant axis w, and the other two (u, v) in cyclic order.
    let w = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let (u, vv) = ((w + 1) % 3, (w + 2) % 3);
    let p2 = v.map(|p| [p[u], p[vv]]);
    let depth = v.map(|p| p[w]);
    let n = grid.resolution as f64;
    let lo = |k: usize| p2.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
    let hi = |k: usize| p2.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
    let range = |l: f64, h: f64| (l.floor().max(0.0) as usize, (h.floor().min(n - 1.0)) as usize);
    let ((i0, i1), (j0, j1)) = (range(lo(0), hi(0)), range(lo(1), hi(1)));
    // Edges as 2-D half-planes, oriented so the triangle is inside (>= 0).
    let orientation = (p2[1][0] - p2[0][0]) * (p2[2][1] - p2[0][1])
        - (p2[1][1] - p2[0][1]) * (p2[2][0] - p2[0][0]);
    let sign = if orientation >= 0.0 { 1.0 } else { -1.0 };
    let edges: Vec<[f64; 3]> = (0..3)
        .map(|e| {
            let (p, q) = (p2[e], p2[(e + 1) % 3]);
            let (nx, ny) = (-(q[1] - p[1]) * sign, (q[0] - p[0]) * sign);
            [nx, ny, -(nx * p[0] + ny * p[1])]
        })
        .collect();
    // Depth plane w = c + du·u + dv·v.
    let (du, dv) = (-normal[u] / normal[w], -normal[vv] / normal[w]);
    let c = depth[0] - du * p2[0][0] - dv * p2[0][1];
    let (dmin, dmax) = (
        depth.iter().copied().fold(f64::INFINITY, f64::min),
        depth.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let mut marked = Vec::new();
    if hi(0) < 0.0 || hi(1) < 0.0 || lo(0) >= n || lo(1) >= n {
        return marked;
    }
    for j in j0..=j1 {
        for i in i0..=i1 {
            let (x, y) = (i as f64, j as f64);
            // The square's corner farthest inside each edge must be inside it.
            let inside = edges.iter().all(|e| {
                let cx = if e[0] >= 0.0 { x + 1.0 } else { x };
                let cy = if e[1] >= 0.0 { y + 1.0 } else { y };
                e[0] * cx + e[1] * cy + e[2] >= 0.0
            });
            if !inside {
                continue;
            }
            let centre = c + du * (x + 0.5) + dv * (y + 0.5);
            let spread = 0.5 * (du.abs() + dv.abs());
            let (z0, z1) = (
                (centre - spread).max(dmin),
                (centre + spread).min(dmax),
            );
            if z1 < 0.0 || z0 >= n {
                continue;
            }
            for k in z0.floor().max(0.0) as usize..=z1.floor().min(n - 1.0) as usize {
                let mut voxel = [0; 3];
                voxel[u] = i;
                voxel[vv] = j;
                voxel[w] = k;
                marked.push(voxel);
            }
        }
    }
    marked
}

/// The occupancy mip chain from level 0 (`level0`, one value per voxel): each coarser voxel the
/// mean of its 8 children.
pub fn mips(grid: &VoxelGrid, level0: &[f64]) -> Vec<f64> {
    let mut chain = level0.to_vec();
    for level in 1..grid.levels() {
        let (side, below) = (grid.side(level), grid.side(level - 1));
        let base = grid.offset(level - 1);
        for z in 0..side {
            for y in 0..side {
                for x in 0..side {
                    let mut sum = 0.0;
                    for k in 0..8 {
                        let c = [2 * x + (k & 1), 2 * y + ((k >> 1) & 1), 2 * z + (k >> 2)];
                        sum += chain[base + c[0] + below * (c[1] + below * c[2])];
                    }
                    chain.push(sum / 8.0);
                }
            }
        }
    }
    chain
}

/// Occupancy at `p` (level-0 voxel units) filtered at level `lod`: trilinear within a level
/// (voxel centres at (i + ½)·2^level, zero outside the cube), linear between levels.
pub fn sample(grid: &VoxelGrid, chain: &[f64], p: DVec3, lod: f64) -> f64 {
    let top = f64::from(grid.levels() - 1);
    let lod = lod.clamp(0.0, top);
    let level = lod.floor() as u32;
    let fine = sample_level(grid, chain, p, level);
    if lod == f64::from(level) {
        return fine;
    }
    let coarse = sample_level(grid, chain, p, level + 1);
    fine + (coarse - fine) * (lod - f64::from(level))
}

fn sample_level(grid: &VoxelGrid, chain: &[f64], p: DVec3, level: u32) -> f64 {
    let side = grid.side(level) as i64;
    let q = p / f64::from(1u32 << level) - 0.5;
    let base = q.floor();
    let f = q - base;
    let offset = grid.offset(level);
    let mut sum = 0.0;
    for k in 0..8 {
        let c = [k & 1, (k >> 1) & 1, k >> 2].map(|b| b as i64);
        let v = [
            base.x as i64 + c[0],
            base.y as i64 + c[1],
            base.z as i64 + c[2],
        ];
        if v.iter().any(|&i| i < 0 || i >= side) {
            continue;
        }
        let w = [f.x, f.y, f.z]
            .iter()
            .zip(c)
            .map(|(f, b)| if b == 1 { *f } else { 1.0 - f })
            .product::<f64>();
        let s = side as usize;
        sum += w * chain[offset + v[0] as usize + s * (v[1] as usize + s * v[2] as usize)];
    }
    sum
}

/// Visibility between `from` and `to` (world space) through a cone of aperture `s` (radius per
/// unit length), marched front to back from [`CONE_START`] voxels, each sample at the level of
/// its radius, until a sample's footprint (its radius, at least a voxel) would come within a
/// voxel of `to` or of the target's own surface: the plane through `to` with unit normal
/// `normal`, within `extent` (world) of `to` along it (spec 001 §4.6; the public code stops 2
/// voxels short of `to`, which lets cones that approach their target's surface at a grazing
/// angle, or narrow ones, be hidden by that surface).
pub fn cone_visibility(
    grid: &VoxelGrid,
    chain: &[f64],
    (from, to, normal): (DVec3, DVec3, DVec3),
    s: f64,
    extent: f64,
) -> f64 {
    let (x, y) = (grid.to_voxels(from), grid.to_voxels(to));
    let distance = (y - x).length();
    if distance == 0.0 {
        return 1.0;
    }
    let direction = (y - x) / distance;
    let half_extent = 0.5 * extent / f64::from(grid.voxel);
    let mut t = CONE_START;
    let mut occlusion = 0.0;
    for _ in 0..CONE_STEPS {
        let r = t * s;
        let p = x + direction * t;
        let clearance = r.max(1.0) + 1.0;
        let height = (p - y).dot(normal);
        let over_target = ((p - y) - normal * height).length() < clearance + half_extent;
        if t + clearance >= distance || (over_target && height <= clearance) {
            break;
        }
        let alpha = sample(grid, chain, p, r.max(1e-30).log2());
        occlusion += (1.0 - occlusion) * alpha;
        t += (2.0 * r / (1.0 - s)).max(1.0);
    }
    (1.0 - occlusion).clamp(0.0, 1.0)
}

/// Aperture of the cone to a block of VALs whose merged VAL is `mean`, `blocks` blocks to a
/// side of a light view `extent` wide at unit distance (light.comp `block_visibility`): the
/// block's angular width from the light, or two standard deviations of its distance over the
/// mean, whichever is wider (spec 001 §4.6 step 2, with tan for the view's extent).
pub fn block_aperture(extent: f64, blocks: u32, mean: &Val) -> f64 {
    let d = mean.depth;
    let sigma = (mean.depth_squared - d * d).max(0.0).sqrt();
    (extent / f64::from(blocks))
        .max(2.0 * sigma / d.max(1e-30))
        .clamp(0.01, 0.95)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> VoxelGrid {
        VoxelGrid {
            min: Vec3::ZERO,
            voxel: 1.0,
            resolution: 16,
        }
    }

    /// A level-0 volume with the voxels `solid` says are full.
    fn volume(g: &VoxelGrid, solid: impl Fn([usize; 3]) -> bool) -> Vec<f64> {
        let n = g.resolution as usize;
        let mut level0 = vec![0.0; n * n * n];
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    if solid([x, y, z]) {
                        level0[g.index([x, y, z])] = 1.0;
                    }
                }
            }
        }
        mips(g, &level0)
    }

    #[test]
    fn a_sealed_wall_blocks_a_narrow_cone_and_open_space_does_not() {
        let g = grid();
        let from = DVec3::new(2.5, 8.0, 8.0);
        let to = DVec3::new(13.5, 8.0, 8.0);
        let empty = volume(&g, |_| false);
        assert_eq!(cone_visibility(&g, &empty, (from, to, DVec3::NEG_X), 0.05, 1.0), 1.0);
        // Two voxels thick, the whole cross-section.
        let wall = volume(&g, |v| v[0] == 7 || v[0] == 8);
        assert_eq!(cone_visibility(&g, &wall, (from, to, DVec3::NEG_X), 0.05, 1.0), 0.0);
        // A wall beside the path leaves a narrow cone untouched.
        let beside = volume(&g, |v| (v[0] == 7 || v[0] == 8) && v[1] >= 12);
        assert_eq!(cone_visibility(&g, &beside, (from, to, DVec3::NEG_X), 0.05, 1.0), 1.0);
        // Half the cross-section blocked, seen by a wide cone: partly visible.
        let half = volume(&g, |v| (v[0] == 7 || v[0] == 8) && v[1] < 8);
        let v = cone_visibility(&g, &half, (from, to, DVec3::NEG_X), 0.4, 1.0);
        assert!(v > 0.05 && v < 0.95, "{v}");
        // A target on the floor, the apex just above that floor's plane and far from the
        // target along it: the march does not stop at the plane, and the wall hides it.
        let floor_to = DVec3::new(13.5, 1.0, 8.0);
        let low = DVec3::new(2.5, 1.5, 8.0);
        assert_eq!(cone_visibility(&g, &wall, (low, floor_to, DVec3::Y), 0.05, 1.0), 0.0);
        assert_eq!(cone_visibility(&g, &empty, (low, floor_to, DVec3::Y), 0.05, 1.0), 1.0);
    }

    #[test]
    fn mips_average_and_sampling_interpolates_between_voxel_centres() {
        let g = grid();
        let chain = volume(&g, |v| v[0] < 8);
        assert_eq!(chain.len(), g.total());
        // Level 4 is one voxel: half full.
        assert_eq!(chain[g.offset(4)], 0.5);
        // Level 0: full at a centre left of the boundary, half-way on it, empty right of it.
        assert_eq!(sample(&g, &chain, DVec3::new(7.5, 8.0, 8.0), 0.0), 1.0);
        assert!((sample(&g, &chain, DVec3::new(8.0, 8.0, 8.0), 0.0) - 0.5).abs() < 1e-12);
        assert_eq!(sample(&g, &chain, DVec3::new(8.5, 8.0, 8.0), 0.0), 0.0);
        // Outside the cube the volume is empty.
        assert_eq!(sample(&g, &chain, DVec3::new(-3.0, 8.0, 8.0), 0.0), 0.0);
    }

    /// Whether triangle `t` (voxel units) and the unit box at `v` overlap by more than a touch
    /// (separating axes:
    /// box faces, triangle normal, the 9 edge cross products).
    fn overlaps(t: [DVec3; 3], v: [usize; 3]) -> bool {
        let centre = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64) + 0.5;
        let p = t.map(|q| q - centre);
        let edges = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
        let mut axes = vec![DVec3::X, DVec3::Y, DVec3::Z, edges[0].cross(edges[1])];
        for e in edges {
            for a in [DVec3::X, DVec3::Y, DVec3::Z] {
                axes.push(e.cross(a));
            }
        }
        axes.iter().all(|axis| {
            let r = 0.5 * (axis.x.abs() + axis.y.abs() + axis.z.abs());
            let d = p.map(|q| q.dot(*axis));
            let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
            !(lo >= r - 1e-9 || hi <= -r + 1e-9)
        })
    }

    #[test]
    fn voxelisation_marks_every_voxel_a_triangle_touches_and_only_those_near_it() {
        let g = grid();
        let triangles = [
            [
                DVec3::new(1.2, 1.7, 2.3),
                DVec3::new(13.9, 4.1, 5.6),
                DVec3::new(5.5, 12.8, 11.1),
            ],
            [
                DVec3::new(3.0, 3.0, 3.0),
                DVec3::new(3.0, 9.0, 3.0),
                DVec3::new(3.0, 3.0, 9.0),
            ],
            [
                DVec3::new(-4.0, 7.3, 7.7),
                DVec3::new(20.0, 7.9, 8.1),
                DVec3::new(8.0, 30.0, 8.4),
            ],
        ];
        for t in triangles {
            let marked = voxelize_triangle(&g, t);
            let n = g.resolution as usize;
            for z in 0..n {
                for y in 0..n {
                    for x in 0..n {
                        let v = [x, y, z];
                        if overlaps(t, v) {
                            assert!(marked.contains(&v), "{v:?} touched but not marked");
                        }
                    }
                }
            }
            // Marked voxels lie within one voxel of the triangle's plane.
            let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
            for v in &marked {
                let centre = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64) + 0.5;
                assert!((centre - t[0]).dot(normal).abs() < 1.5, "{v:?} far from the plane");
            }
        }
        assert!(voxelize_triangle(&g, [DVec3::ONE; 3]).is_empty());
    }
}
