//! The geometry (blocking) lattice of seed 000: every scene triangle is sampled uniformly (a
//! fixed-seed stream per triangle, rejection from the parallelogram as in the thesis), and each
//! sample adds its area density `(A/n)/d²` times the SH lobe of its normal to the cell containing
//! it (no half-cell offset). The result is view-independent and has no holes.
//!
//! The thesis leaves the lobe's sign open (prose and code disagree) and vkgi's surfaces are
//! two-sided (normals follow the OBJ winding, which nothing guarantees), so the lobe is a choice:
//! `front` SH_cos(N) (the thesis code), `back` SH_cos(-N), or `two-sided` SH_cos(N) + SH_cos(-N),
//! which does not depend on winding. docs/lpv.md records the two-rooms test that decided the
//! default. Densities are normalised so that a surface filling a cell's cross-section, facing
//! the direction of propagation, blocks a face-neighbour transfer completely.

use glam::{DVec3, DVec4, Vec3};

use super::lattice::Lattice;
use crate::gi::shared::sh;
use super::transfer::TransferVectors;
use crate::scene::Mesh;

/// Which SH lobe a surface sample adds to the geometry lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum BlockingLobe {
    /// SH_cos(N): blocks light travelling along the stored normal (the thesis code).
    Front,
    /// SH_cos(-N): blocks light travelling against the stored normal.
    Back,
    /// Both: blocks either way, whatever the winding.
    TwoSided,
    /// No blocking at all (no indirect shadows; for comparison).
    None,
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

/// Blocking of a unit-density surface facing the face-neighbour direction: the normaliser.
pub fn unit_blocking(transfer: &TransferVectors) -> f64 {
    let face = transfer
        .neighbours
        .iter()
        .find(|n| n.offset == glam::IVec3::X)
        .map(|n| n.transfer)
        .unwrap_or(DVec4::ZERO);
    sh::cosine_lobe(DVec3::X).dot(face)
}

/// The geometry lattice (one SH vector per cell) of `mesh`.
pub fn build(
    mesh: &Mesh,
    lattice: &Lattice,
    transfer: &TransferVectors,
    lobe: BlockingLobe,
) -> Vec<DVec4> {
    let mut cells = vec![DVec4::ZERO; lattice.cell_count()];
    let d2 = f64::from(lattice.cell_size).powi(2);
    let norm = 1.0 / unit_blocking(transfer);
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.triangle(t).map(|v| v.as_dvec3());
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        if area <= 0.0 {
            continue;
        }
        let normal = cross / (2.0 * area);
        let shape = match lobe {
            BlockingLobe::Front => sh::cosine_lobe(normal),
            BlockingLobe::Back => sh::cosine_lobe(-normal),
            BlockingLobe::TwoSided => sh::cosine_lobe(normal) + sh::cosine_lobe(-normal),
            BlockingLobe::None => return cells,
        };
        let samples =
            ((SAMPLES_PER_CELL_AREA * area / d2).ceil() as u64).clamp(1, MAX_SAMPLES_PER_TRIANGLE);
        let weight = area / samples as f64 / d2 * norm;
        let mut rand = stream(0x5eed_0000_0000_0000 ^ t as u64);
        let mut kept = 0;
        while kept < samples {
            let (u, v) = (rand(), rand());
            if u + v > 1.0 {
                continue;
            }
            kept += 1;
            let p = a + (b - a) * u + (c - a) * v;
            if let Some(cell) = lattice.cell_of(Vec3::new(p.x as f32, p.y as f32, p.z as f32)) {
                cells[lattice.index(cell)] += shape * weight;
            }
        }
    }
    cells
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_wall_filling_a_cell_blocks_a_face_transfer_completely() {
        // A 1 x 1 square at x = 0.5 inside a 2 x 1 x 1 lattice of unit cells.
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
        let face = transfer
            .neighbours
            .iter()
            .find(|n| n.offset == glam::IVec3::X)
            .unwrap()
            .transfer;
        let back = transfer
            .neighbours
            .iter()
            .find(|n| n.offset == glam::IVec3::NEG_X)
            .unwrap()
            .transfer;
        let front = build(&mesh, &lattice, &transfer, BlockingLobe::Front);
        assert!(
            (front[0].dot(face) - 1.0).abs() < 1e-9,
            "full blocking along +x: {}",
            front[0].dot(face)
        );
        assert!(
            front[0].dot(back) < 0.2,
            "little blocking against the normal"
        );
        assert_eq!(front[1], DVec4::ZERO);
        let two = build(&mesh, &lattice, &transfer, BlockingLobe::TwoSided);
        assert!(
            (two[0].dot(face) - two[0].dot(back)).abs() < 1e-12,
            "two-sided blocks both ways"
        );
        assert!(two[0].dot(face) > 0.8);
    }
}
