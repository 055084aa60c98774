//! The geometry (blocking) lattice of seed 000, view-independent and without holes. Three
//! families of blocking functions ([`BlockingLobe`]):
//! * **The thesis's SH lobes** (one word per cell): every scene triangle is sampled uniformly (a
//!   fixed-seed stream per triangle, rejection from the parallelogram as in the thesis), and each
//!   sample adds its area density `(A/n)/d²` times the lobe to the cell containing it (no
//!   half-cell offset): `front` SH_cos(N) (the thesis code), `back` SH_cos(-N), or `two-sided`
//!   (the default) SH_cos(N) + SH_cos(-N), evaluated as ⟨B|Γ_d⟩ and normalised so that a surface
//!   filling a cell's cross-section, facing the direction of propagation, blocks a face-neighbour
//!   transfer completely. In 2-band SH a one-sided lobe still blocks a grazing transfer at about
//!   half its head-on strength, and the two-sided sum cancels the linear band, so it blocks every
//!   direction alike (about 0.89 of any transfer through a cell-filling surface, grazing ones
//!   included). It is the default because it is the more accurate on three of the four scenes
//!   measured (docs/lpv.md): its over-blocking darkens the light that 2-band lobes send along
//!   surfaces, which the lookup would otherwise read as the surfaces lighting themselves.
//! * **Projected area** ([`super::projected`], three words per cell), from the same samples: a
//!   surface blocks the area it shows the direction of travel, times the distance travelled: a
//!   wall blocks light crossing it and not light running along it. `oriented` makes a surface
//!   one-way where one of its sides faces the void ([`super::void_side`]): a room's walls and
//!   floor then block only light leaving the room. `projected` blocks both ways everywhere.
//! * **Visibility** ([`super::visibility`], four words per cell): a transfer is blocked when the
//!   segment between the two cells' centres crosses a surface: watertight for closed surfaces.

use std::collections::HashMap;

use glam::{DVec3, DVec4, IVec3, Vec3};

use super::lattice::{CellBox, Lattice};
use super::projected;
use super::transfer::TransferVectors;
use super::visibility;
use super::void_side::Occupancy;
use crate::gi::shared::sh;
use crate::scene::Mesh;
use crate::scene::dynamic::Aabb;

/// What a surface sample adds to the geometry lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum BlockingLobe {
    /// The projected area, one-way toward the void where one side of a surface faces it.
    Oriented,
    /// The projected area, both ways everywhere.
    Projected,
    /// Whether the segment between the cells' centres crosses a surface.
    Visibility,
    /// SH_cos(N): blocks light travelling along the stored normal (the thesis code).
    Front,
    /// SH_cos(-N): blocks light travelling against the stored normal.
    Back,
    /// Both SH lobes: blocks either way, whatever the winding, and every direction alike.
    TwoSided,
    /// No blocking at all (no indirect shadows; for comparison).
    None,
}

impl BlockingLobe {
    /// SH-sized words per cell.
    pub fn words_per_cell(self) -> usize {
        match self {
            BlockingLobe::Oriented | BlockingLobe::Projected => projected::WORDS,
            BlockingLobe::Visibility => visibility::WORDS,
            _ => 1,
        }
    }
}

/// The geometry lattice: `words_per_cell` consecutive words per cell, in lattice order.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryLattice {
    pub lobe: BlockingLobe,
    pub words: Vec<DVec4>,
}

/// The words of one cell, padded with zeros to the widest model.
pub type CellWords = [DVec4; visibility::WORDS];

impl GeometryLattice {
    /// A lattice of `cells` cells that blocks nothing.
    pub fn empty(lobe: BlockingLobe, cells: usize) -> GeometryLattice {
        GeometryLattice {
            lobe,
            words: vec![DVec4::ZERO; cells * lobe.words_per_cell()],
        }
    }

    /// The words of cell `index`.
    pub fn cell(&self, index: usize) -> &[DVec4] {
        let k = self.lobe.words_per_cell();
        &self.words[index * k..(index + 1) * k]
    }

    /// The words of the cell at integer coordinates `c` (zero outside the lattice).
    pub fn words_at(&self, lattice: &Lattice, c: IVec3) -> CellWords {
        let mut words = CellWords::default();
        if let Some(c) = lattice.checked(c) {
            for (w, stored) in words.iter_mut().zip(self.cell(lattice.index(c))) {
                *w = *stored;
            }
        }
        words
    }

    /// How much of a transfer to the neighbour at `offset` (in cells), with transfer vector
    /// `transfer`, is blocked, from the geometry words of its source and its destination (before
    /// the step clamps it to [0, 1]).
    pub fn blocking(
        &self,
        source: CellWords,
        destination: CellWords,
        transfer: DVec4,
        offset: IVec3,
    ) -> f64 {
        match self.lobe {
            BlockingLobe::Oriented | BlockingLobe::Projected => {
                let [a, b, c, _] = source;
                projected::blocking([a, b, c], offset.as_dvec3())
            }
            BlockingLobe::Visibility => visibility::blocking(&source, &destination, offset),
            _ => source[0].dot(transfer),
        }
    }

    /// Every word times `factor` (the blocking strength).
    pub fn scaled(mut self, factor: f64) -> GeometryLattice {
        for w in &mut self.words {
            *w *= factor;
        }
        self
    }

    /// The words as the GPU stores them.
    pub fn to_f32(&self) -> Vec<[f32; 4]> {
        self.words.iter().map(|w| w.as_vec4().to_array()).collect()
    }
}

/// Samples per unit of `area / cell area` (the thesis leaves the density open; ≥ 1 per
/// triangle).
const SAMPLES_PER_CELL_AREA: f64 = 8.0;
/// Cap on samples per triangle, so huge triangles in fine lattices stay affordable.
const MAX_SAMPLES_PER_TRIANGLE: u64 = 1 << 20;

/// SplitMix64 stream for one triangle.
fn stream(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Blocking of a unit-density surface facing the face-neighbour direction under the SH lobes:
/// their normaliser.
pub fn unit_blocking(transfer: &TransferVectors) -> f64 {
    let face = transfer
        .neighbours
        .iter()
        .find(|n| n.offset == glam::IVec3::X)
        .map(|n| n.transfer)
        .unwrap_or(DVec4::ZERO);
    sh::cosine_lobe(DVec3::X).dot(face)
}

/// One uniform sample of a triangle: where, the triangle's index and unit normal, and the area
/// density it carries in cells of area `d²`.
struct Sample {
    triangle: usize,
    position: DVec3,
    normal: DVec3,
    density: f64,
}

/// Every area sample of every non-degenerate triangle of `mesh` that `keep` keeps, in a fixed
/// order (a triangle's samples depend on it alone).
fn for_each_sample(
    mesh: &Mesh,
    lattice: &Lattice,
    keep: impl Fn(usize) -> bool,
    mut f: impl FnMut(&Sample),
) {
    let d2 = f64::from(lattice.cell_size).powi(2);
    for t in (0..mesh.triangle_count()).filter(|&t| keep(t)) {
        let [a, b, c] = mesh.triangle(t).map(|v| v.as_dvec3());
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        if area <= 0.0 {
            continue;
        }
        let samples =
            ((SAMPLES_PER_CELL_AREA * area / d2).ceil() as u64).clamp(1, MAX_SAMPLES_PER_TRIANGLE);
        let mut sample = Sample {
            triangle: t,
            position: a,
            normal: cross / (2.0 * area),
            density: area / samples as f64 / d2,
        };
        let mut rand = stream(0x5eed_0000_0000_0000 ^ t as u64);
        let mut kept = 0;
        while kept < samples {
            let (u, v) = (rand(), rand());
            if u + v > 1.0 {
                continue;
            }
            kept += 1;
            sample.position = a + (b - a) * u + (c - a) * v;
            f(&sample);
        }
    }
}

/// The words one unit of area density of `sample` adds (`norm`: the SH lobes' normaliser,
/// `outward`: the side facing the void, for one-way blocking); none for no blocking.
fn unit_density_words(
    lobe: BlockingLobe,
    normal: DVec3,
    norm: f64,
    outward: impl FnOnce() -> Option<DVec3>,
) -> Option<CellWords> {
    let projected_words = |[a, b, c]: [DVec4; projected::WORDS]| [a, b, c, DVec4::ZERO];
    let sh_lobe = match lobe {
        BlockingLobe::Oriented => {
            return Some(projected_words(projected::surface_words(normal, outward())));
        }
        BlockingLobe::Projected => {
            return Some(projected_words(projected::surface_words(normal, None)));
        }
        BlockingLobe::Front => sh::cosine_lobe(normal),
        BlockingLobe::Back => sh::cosine_lobe(-normal),
        BlockingLobe::TwoSided => sh::cosine_lobe(normal) + sh::cosine_lobe(-normal),
        BlockingLobe::Visibility | BlockingLobe::None => return None,
    };
    Some([sh_lobe * norm, DVec4::ZERO, DVec4::ZERO, DVec4::ZERO])
}

/// The geometry lattice of `mesh`.
pub fn build(
    mesh: &Mesh,
    lattice: &Lattice,
    transfer: &TransferVectors,
    lobe: BlockingLobe,
) -> GeometryLattice {
    build_region(mesh, lattice, transfer, lobe, &lattice.all_cells())
}

/// The cells whose words change when the geometry in the world boxes `regions` moves: the
/// cells the boxes touch, widened by a cell, and merged where they touch; every cell for
/// oriented blocking, whose side facing the void depends on the whole lattice; none without
/// blocking. The margin covers samples binned in f32 next to a cell's face and, for visibility
/// blocking, the segments of the cells whose centres lie within a cell of a box (a segment
/// reaches the next centre: half a cell beyond the cell's own face, half a cell to spare).
pub fn touched_cells(lattice: &Lattice, lobe: BlockingLobe, regions: &[Aabb]) -> Vec<CellBox> {
    match lobe {
        BlockingLobe::None => return Vec::new(),
        BlockingLobe::Oriented => return vec![lattice.all_cells()],
        _ => {}
    }
    let boxes = regions
        .iter()
        .filter_map(|r| lattice.cells_touching(r.min, r.max, 1))
        .collect();
    CellBox::merged(boxes)
}

/// Whether triangle `t` of `mesh` may reach into the world box `min`..`max` (its own box
/// overlaps it).
pub(super) fn overlaps(mesh: &Mesh, t: usize, (min, max): (Vec3, Vec3)) -> bool {
    let [a, b, c] = mesh.triangle(t);
    a.min(b).min(c).cmple(max).all() && a.max(b).max(c).cmpge(min).all()
}

/// The geometry words of the cells of `region` alone, in its order (see
/// [`CellBox::local_index`]), exactly as [`build`] gives them for the whole lattice: a cell sums
/// the same samples in the same order, from the triangles whose boxes reach it. After geometry
/// moves, rebuilding the cells it touched before and after gives the lattice of the moved
/// scene (oriented blocking excepted: the side facing the void is a property of the whole
/// lattice, so it is rebuilt whole).
pub fn build_region(
    mesh: &Mesh,
    lattice: &Lattice,
    transfer: &TransferVectors,
    lobe: BlockingLobe,
    region: &CellBox,
) -> GeometryLattice {
    if lobe == BlockingLobe::Visibility {
        return GeometryLattice {
            lobe,
            words: visibility::build_region(mesh, lattice, region),
        };
    }
    let mut out = GeometryLattice::empty(lobe, region.count());
    // Only oriented blocking needs the occupancy (a first pass over every sample).
    let occupancy = (lobe == BlockingLobe::Oriented).then(|| {
        let mut occupancy = Occupancy::new(lattice);
        for_each_sample(mesh, lattice, |_| true, |s| occupancy.mark(s.position));
        occupancy
    });
    // Samples are placed in f64 and binned in f32: a margin of a thousandth of a cell keeps
    // every triangle with a sample in the region.
    let (min, max) = lattice.world_box(region);
    let margin = Vec3::splat(1e-3 * lattice.cell_size);
    let reach = (min - margin, max + margin);
    let k = lobe.words_per_cell();
    let norm = 1.0 / unit_blocking(transfer);
    // The current triangle's side facing the void, found once per cell it covers.
    let mut sides: HashMap<usize, Option<DVec3>> = HashMap::new();
    let mut sides_of = usize::MAX;
    let keep = |t: usize| overlaps(mesh, t, reach);
    for_each_sample(mesh, lattice, keep, |s| {
        let Some(i) = lattice
            .cell_of(s.position.as_vec3())
            .and_then(|c| region.local_index(c))
        else {
            return;
        };
        if sides_of != s.triangle {
            sides.clear();
            sides_of = s.triangle;
        }
        let outward = || {
            *sides
                .entry(i)
                .or_insert_with(|| occupancy.as_ref()?.outward(s.position, s.normal))
        };
        let Some(words) = unit_density_words(lobe, s.normal, norm, outward) else {
            return;
        };
        for (word, add) in out.words[i * k..(i + 1) * k].iter_mut().zip(words) {
            *word += add * s.density;
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A 1 x 1 square at x = 0.5 (normal +x) in a 2 x 1 x 1 lattice of unit cells.
    fn wall_in_a_cell(lobe: BlockingLobe) -> (GeometryLattice, TransferVectors) {
        let mut mesh = Mesh::default();
        let corners = [
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(0.5, 1.0, 1.0),
            Vec3::new(0.5, 0.0, 1.0),
        ];
        for tri in [[0, 1, 2], [0, 2, 3]] {
            mesh.push_triangle(tri.map(|i| corners[i]), [Vec3::X; 3], 0);
        }
        let lattice = Lattice::fit(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), 2).unwrap();
        let transfer = TransferVectors::compute(2000, 3);
        (build(&mesh, &lattice, &transfer, lobe), transfer)
    }

    /// The wall cell's blocking of the transfer toward neighbour `offset`.
    fn toward(g: &GeometryLattice, t: &TransferVectors, offset: IVec3) -> f64 {
        let n = t.neighbours.iter().find(|n| n.offset == offset).unwrap();
        let lattice = Lattice::fit(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), 2).unwrap();
        let words = g.words_at(&lattice, IVec3::ZERO);
        g.blocking(words, g.words_at(&lattice, offset), n.transfer, offset)
    }

    #[test]
    fn a_wall_filling_a_cell_blocks_a_face_transfer_completely() {
        let (front, t) = wall_in_a_cell(BlockingLobe::Front);
        let through = toward(&front, &t, IVec3::X);
        assert!((through - 1.0).abs() < 1e-9, "full blocking along +x: {through}");
        assert!(toward(&front, &t, IVec3::NEG_X) < 0.2, "little against the normal");
        assert_eq!(front.cell(1), [DVec4::ZERO]);
        // The wall is a partition of the lattice (both sides reach its border without meeting
        // anything, so neither is the outside): oriented blocking is two-way there too.
        let (oriented, t) = wall_in_a_cell(BlockingLobe::Oriented);
        let b = toward(&oriented, &t, IVec3::NEG_X);
        assert!((b - 1.0).abs() < 1e-9, "{b}");
        let (two, t) = wall_in_a_cell(BlockingLobe::TwoSided);
        let (x, back) = (toward(&two, &t, IVec3::X), toward(&two, &t, IVec3::NEG_X));
        assert!((x - back).abs() < 1e-12, "two-sided blocks both ways");
        assert!(x > 0.8);
        let (projected, t) = wall_in_a_cell(BlockingLobe::Projected);
        for offset in [IVec3::X, IVec3::NEG_X] {
            let b = toward(&projected, &t, offset);
            assert!((b - 1.0).abs() < 1e-9, "projected, {offset}: {b}");
        }
        // A diagonal transfer sees the wall foreshortened (|N·ω| = 1/√2 and 1/√3) over a
        // longer step (√2 and √3 cells): it crosses it once all the same.
        for offset in [IVec3::new(1, 1, 0), IVec3::new(-1, 1, -1)] {
            let b = toward(&projected, &t, offset);
            assert!((b - 1.0).abs() < 1e-9, "{offset}: {b}");
        }
    }

    #[test]
    fn rebuilding_the_cells_moved_geometry_touches_gives_the_moved_scenes_lattice() {
        use crate::scene::Scene;
        use crate::scene::dynamic::{Moved, Path};
        let mut scene = Scene::load("cornell").unwrap();
        let n = scene.mesh.triangle_count();
        let block: Vec<usize> = (n - 10..n).collect();
        let lattice_of = |scene: &Scene| Lattice::fit(scene.bounds_min, scene.bounds_max, 16);
        let cell = lattice_of(&scene).unwrap().cell_size;
        // A long move, a short one, and one of exactly two cells (faces on cell boundaries).
        let keys = vec![
            (0, Vec3::ZERO),
            (1, Vec3::new(-0.13, 0.0, 0.07)),
            (2, Vec3::new(-0.1127, 0.0031, 0.0389)),
            (3, Vec3::new(-0.1127 + 2.0 * cell, 0.0031, 0.0389)),
        ];
        scene.add_dynamic("tall", &block, Path::new(keys, false).unwrap()).unwrap();
        let lattice = lattice_of(&scene).unwrap();
        let transfer = TransferVectors::compute(2000, 3);
        for lobe in [
            BlockingLobe::TwoSided,
            BlockingLobe::Front,
            BlockingLobe::Projected,
            BlockingLobe::Oriented,
            BlockingLobe::Visibility,
        ] {
            for frame in 1..=3 {
                scene.pose(frame - 1);
                let mut spliced = build(&scene.mesh, &lattice, &transfer, lobe);
                let moved = scene.pose(frame);
                let after = build(&scene.mesh, &lattice, &transfer, lobe);
                assert_ne!(spliced, after, "{lobe:?}: the block moved");
                let k = lobe.words_per_cell();
                let mut rebuilt = 0;
                for region in touched_cells(&lattice, lobe, &Moved::regions(&moved)) {
                    let words = build_region(&scene.mesh, &lattice, &transfer, lobe, &region);
                    for (local, cell) in region.cells().enumerate() {
                        let i = lattice.index(cell);
                        spliced.words[i * k..(i + 1) * k].copy_from_slice(words.cell(local));
                    }
                    rebuilt += region.count();
                }
                assert_eq!(spliced, after, "{lobe:?}, move {frame}");
                let part = rebuilt as f64 / lattice.cell_count() as f64;
                if lobe == BlockingLobe::Oriented {
                    assert_eq!(part, 1.0);
                } else {
                    // The block fills a tenth of the box; before and after, with the margins,
                    // up to 35%.
                    assert!(part < 0.4, "{lobe:?}: {rebuilt} of {} cells", lattice.cell_count());
                }
            }
        }
    }

    #[test]
    fn only_the_projected_area_lets_light_run_along_a_wall() {
        let grazing = [IVec3::Y, IVec3::Z, IVec3::new(0, 1, -1)];
        let (projected, t) = wall_in_a_cell(BlockingLobe::Projected);
        for offset in grazing {
            assert!(toward(&projected, &t, offset).abs() < 1e-12, "{offset}");
        }
        // The thesis's lobes block a grazing face transfer at about half their head-on blocking
        // or more: 2-band SH cannot be sharper.
        for lobe in [BlockingLobe::Front, BlockingLobe::Back, BlockingLobe::TwoSided] {
            let (g, t) = wall_in_a_cell(lobe);
            let head_on = toward(&g, &t, IVec3::X).max(toward(&g, &t, IVec3::NEG_X));
            let along = toward(&g, &t, IVec3::Y);
            assert!(along > 0.4 * head_on, "{lobe:?}: {along} against {head_on}");
        }
    }
}
