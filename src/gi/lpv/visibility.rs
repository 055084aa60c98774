//! The visibility blocking model of the geometry lattice ([`super::geometry`]): the transfer
//! between two neighbouring cells is blocked when the segment between their centres crosses a
//! surface. A closed surface cuts every segment from a centre inside it to one outside, so a
//! sealed box keeps its light whatever its size relative to the cells (the area-density models
//! leak through the partly covered cells at its edges), and a surface running between two
//! centres blocks nothing. Objects smaller than a cell block all or nothing.
//!
//! A segment is symmetric, so each cell stores the 13 segments toward the neighbours of the
//! upper half of the 26 (offset index (o.x+1) + 3(o.y+1) + 9(o.z+1) above 13, the centre's), in
//! four SH-sized words; a transfer toward a lower-half offset reads the destination's entry for
//! the opposite offset. shaders-glsl/gi/lpv/blocking.glsl is the same in f32.

use glam::{DVec4, IVec3, Vec3};

use super::geometry::overlaps;
use super::lattice::{CellBox, Lattice};
use crate::scene::Mesh;
use crate::scene::bvh::Bvh;

/// SH-sized words per cell (13 entries and 3 unused).
pub const WORDS: usize = 4;

/// Segment ends move by this fixed fraction of a cell (an irrational direction), so that a
/// surface through cell centres, as axis-aligned walls at round coordinates can be, is crossed
/// or not rather than grazed.
const JITTER: [f32; 3] = [0.000_731, 0.000_419, 0.000_283];

/// The index (0..27, 13 the centre) of a neighbour offset.
fn offset_index(o: IVec3) -> i32 {
    (o.x + 1) + 3 * (o.y + 1) + 9 * (o.z + 1)
}

/// The entry of a transfer toward `offset`: its number among the 13, and whether the
/// destination (not the source) stores it.
fn entry(offset: IVec3) -> (usize, bool) {
    let i = offset_index(offset);
    if i > 13 {
        ((i - 14) as usize, false)
    } else {
        ((12 - i) as usize, true)
    }
}

/// The 13 upper-half offsets, in entry order.
fn upper_offsets() -> impl Iterator<Item = IVec3> {
    (14..27).map(|i| IVec3::new(i % 3, (i / 3) % 3, i / 9) - 1)
}

/// The visibility words of the cells of `region` (in its order, see
/// [`CellBox::local_index`]) for `mesh`: 1 where the segment toward the neighbour crosses a
/// surface, 0 where not. Only the triangles whose boxes reach the region's segments are
/// searched: whether a segment crosses any triangle does not depend on the others.
pub fn build_region(mesh: &Mesh, lattice: &Lattice, region: &CellBox) -> Vec<DVec4> {
    let d = lattice.cell_size;
    // Segments run from a centre (plus the jitter) to a neighbour's: at most a cell and a half
    // beyond the region's box.
    let (min, max) = lattice.world_box(region);
    let reach = (min - 1.5 * d, max + 1.5 * d);
    let nearby;
    let mesh = if *region == lattice.all_cells() {
        mesh
    } else {
        let mut part = Mesh::default();
        for t in (0..mesh.triangle_count()).filter(|&t| overlaps(mesh, t, reach)) {
            part.push_triangle(mesh.triangle(t), [Vec3::ZERO; 3], 0);
        }
        nearby = part;
        &nearby
    };
    let mut words = vec![DVec4::ZERO; region.count() * WORDS];
    if mesh.triangle_count() == 0 {
        return words;
    }
    let bvh = Bvh::build(mesh);
    let jitter = Vec3::from(JITTER) * d;
    for (local, cell) in region.cells().enumerate() {
        let cell = cell.as_ivec3();
        let from = lattice.cell_centre(cell.as_uvec3()).as_vec3() + jitter;
        let base = local * WORDS;
        for (k, o) in upper_offsets().enumerate() {
            if lattice.checked(cell + o).is_none() {
                continue;
            }
            let to = o.as_vec3() * d;
            let length = to.length();
            if bvh.occluded(from, to / length, 0.0, length) {
                words[base + k / 4][k % 4] = 1.0;
            }
        }
    }
    words
}

/// How much of the transfer toward `offset` is blocked, from the source's and the
/// destination's words.
pub fn blocking(source: &[DVec4], destination: &[DVec4], offset: IVec3) -> f64 {
    let (k, in_destination) = entry(offset);
    let words = if in_destination { destination } else { source };
    words[k / 4][k % 4]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_offset_has_one_entry_shared_with_its_opposite() {
        let mut seen = [0; 13];
        for z in -1..=1 {
            for y in -1..=1 {
                for x in -1..=1 {
                    let o = IVec3::new(x, y, z);
                    if o == IVec3::ZERO {
                        continue;
                    }
                    let (k, flipped) = entry(o);
                    let (k_back, flipped_back) = entry(-o);
                    assert_eq!(k, k_back);
                    assert_ne!(flipped, flipped_back);
                    if !flipped {
                        seen[k] += 1;
                        assert_eq!(upper_offsets().nth(k), Some(o));
                    }
                }
            }
        }
        assert_eq!(seen, [1; 13]);
    }

    #[test]
    fn a_closed_box_cuts_every_segment_out_of_it_and_none_along_a_wall() {
        // A 4 x 4 x 4 lattice of unit cells; a closed box around the centres of cells 1..=2.
        let lattice = Lattice::fit(Vec3::ZERO, Vec3::splat(4.0), 4).unwrap();
        let mut mesh = Mesh::default();
        mesh.push_cuboid(Vec3::splat(1.2), Vec3::splat(2.8), 0);
        let words = build_region(&mesh, &lattice, &lattice.all_cells());
        let cell = |c: IVec3| &words[lattice.index(c.as_uvec3()) * WORDS..][..WORDS];
        let inside = |c: IVec3| c.cmpge(IVec3::ONE).all() && c.cmple(IVec3::splat(2)).all();
        let mut crossing = 0;
        for i in 0..64 {
            let c = IVec3::new(i % 4, (i / 4) % 4, i / 16);
            for o in upper_offsets().chain(upper_offsets().map(|o| -o)) {
                let n = c + o;
                if lattice.checked(n).is_none() {
                    continue;
                }
                let b = blocking(cell(c), cell(n), o);
                assert_eq!(b, f64::from(u8::from(inside(c) != inside(n))), "{c} -> {n}");
                crossing += usize::from(inside(c) != inside(n));
            }
        }
        assert!(crossing > 100, "{crossing}");
    }
}
