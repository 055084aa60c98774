//! The LPV passes in f64 on the CPU, operation for operation as the compute shaders do them:
//! VPL injection, the incremental merge, one 26-neighbour (ILPV) step and one 6-neighbour
//! (classic LPV) step. Tests compare the GPU against these.

use glam::{DVec3, DVec4, IVec3};

use super::geometry::GeometryLattice;
use super::lattice::Lattice;
use super::technique::InjectToward;
use crate::gi::shared::sh;
use super::transfer::{FaceScheme, TransferVectors};

/// A virtual point light: a reflective-shadow-map texel.
#[derive(Clone, Copy, Debug)]
pub struct Vpl {
    pub position: DVec3,
    pub normal: DVec3,
    /// Reflected flux per channel (W).
    pub flux: DVec3,
    /// The position of the light it reflects.
    pub light: DVec3,
}

/// Lattice-normalised medium coefficients and whether blocking applies this step.
#[derive(Clone, Copy, Debug)]
pub struct StepParams {
    pub absorption: f64,
    pub scattering: f64,
    pub use_blocking: bool,
}

/// Inject VPLs as clamped-cosine intensity lobes (Φ/π SH_cos(n)) into the cell `offset` cells
/// along their normal, or toward their light (at most half way); returns the R, G, B lattices.
pub fn inject(
    lattice: &Lattice,
    vpls: &[Vpl],
    offset: f64,
    toward: InjectToward,
) -> [Vec<DVec4>; 3] {
    let mut out = [(); 3].map(|_| vec![DVec4::ZERO; lattice.cell_count()]);
    let shift = offset * f64::from(lattice.cell_size);
    for v in vpls {
        let p = match toward {
            InjectToward::Normal => v.position + v.normal * shift,
            InjectToward::Light => {
                let to_light = v.light - v.position;
                let distance = to_light.length();
                v.position + to_light * (shift.min(0.5 * distance) / distance.max(1e-30))
            }
        };
        let Some(cell) = lattice.cell_of(p.as_vec3()) else {
            continue;
        };
        let i = lattice.index(cell);
        let lobe = sh::cosine_lobe(v.normal);
        for (c, channel) in out.iter_mut().enumerate() {
            channel[i] += lobe * (v.flux[c] / std::f64::consts::PI);
        }
    }
    out
}

/// The incremental blend in place: `current = current * b + previous * a`.
pub fn merge(current: &mut [DVec4], previous: &[DVec4], a: f64, b: f64) {
    for (c, p) in current.iter_mut().zip(previous) {
        *c = *c * b + *p * a;
    }
}

fn fetch(lattice: &Lattice, cells: &[DVec4], c: IVec3) -> DVec4 {
    lattice
        .checked(c)
        .map_or(DVec4::ZERO, |c| cells[lattice.index(c)])
}

fn each_cell(lattice: &Lattice, mut f: impl FnMut(IVec3) -> DVec4) -> Vec<DVec4> {
    let d = lattice.dims.as_ivec3();
    let mut out = Vec::with_capacity(lattice.cell_count());
    for z in 0..d.z {
        for y in 0..d.y {
            for x in 0..d.x {
                out.push(f(IVec3::new(x, y, z)));
            }
        }
    }
    out
}

/// The medium of one step applied to a cell before transport: isotropic scattering turns the
/// scattered part of the directional band into the DC band (the thesis's in-step out-scatter
/// term, γ_j ∝ Γ_j.x, sums to exactly this over the 26 neighbours because Σ_j Γ_j.x² = 1 at the
/// calibrated κ), and absorption takes its part of both.
pub fn medium_mix(l: DVec4, absorption: f64, scattering: f64) -> DVec4 {
    let directional = 1.0 - absorption - scattering;
    DVec4::new(
        l.x * (1.0 - absorption),
        l.y * directional,
        l.z * directional,
        l.w * directional,
    )
}

/// The clamp in the 26-neighbour step drops negative transfers, which adds energy for peaked
/// distributions (a single VPL lobe gains 1.6% in its first step). Clamp compensation applies
/// the step's medium to each cell ([`medium_mix`]) and scales it so that the step, now pure
/// transport, moves exactly the energy the medium left: the factor is
/// E / Σ_j max(0, ⟨L|Γ_j⟩) ⟨Γ_j|1⟩ (exact, because the clamp commutes with positive scales).
pub fn compensate_clamp(cells: &mut [DVec4], t: &TransferVectors, absorption: f64, scattering: f64) {
    for l in cells.iter_mut() {
        *l = medium_mix(*l, absorption, scattering);
        let out: f64 = t
            .neighbours
            .iter()
            .map(|n| l.dot(n.transfer).max(0.0) * n.transfer.x)
            .sum();
        if out > 0.0 && l.x > 0.0 {
            *l *= l.x / out;
        }
    }
}

/// One 26-neighbour gather step (seed 000, Listing 5.2): absorption and scattering, blocking by
/// the source cell's geometry, clamping negative transfers to zero. The clamp acts on the
/// transported light alone (the thesis clamps it with the in-scattered light, which then
/// cancels negative transfers instead of adding to the sum: energy the medium did not absorb).
pub fn step_26(
    lattice: &Lattice,
    src: &[DVec4],
    geometry: &GeometryLattice,
    t: &TransferVectors,
    p: StepParams,
) -> Vec<DVec4> {
    let inv_asn = 1.0 - p.scattering - p.absorption;
    let scatter = sh::SQRT_PI_2 * p.scattering;
    let use_blocking = if p.use_blocking { 1.0 } else { 0.0 };
    each_cell(lattice, |c| {
        let mut dst = DVec4::ZERO;
        for n in &t.neighbours {
            let s = c - n.offset;
            let l = fetch(lattice, src, s);
            let (source, destination) = (geometry.words_at(lattice, s), geometry.words_at(lattice, c));
            let b = geometry.blocking(source, destination, n.transfer, n.offset);
            let outscattered = l.x * scatter;
            let blocking = (1.0 - use_blocking * b).clamp(0.0, 1.0);
            let factor =
                ((inv_asn * l.dot(n.transfer)).max(0.0) + outscattered * n.outscatter) * blocking;
            dst += n.transfer * factor;
        }
        dst
    })
}

/// One 6-neighbour step (Kaplanyan & Dachsbacher 2010): from each face neighbour, the flux
/// through each of the 5 faces of this cell other than the shared one (solid angle times the
/// source's intensity toward the face centre), re-emitted as a cosine lobe around the face
/// normal. Blocking uses the mean geometry of source and destination (the shared face) with
/// the thesis's SH lobes, the source's with the projected-area models (see kd10_step.glsl).
pub fn step_6(
    lattice: &Lattice,
    src: &[DVec4],
    geometry: &GeometryLattice,
    faces: &FaceScheme,
    t: &TransferVectors,
    use_blocking: bool,
) -> Vec<DVec4> {
    let use_blocking = if use_blocking { 1.0 } else { 0.0 };
    each_cell(lattice, |c| {
        let mut dst = DVec4::ZERO;
        for (axis, axis_faces) in &faces.axes {
            let s = c - *axis;
            let l = fetch(lattice, src, s);
            let (a, b) = (geometry.words_at(lattice, s), geometry.words_at(lattice, c));
            let blocker = if geometry.lobe.words_per_cell() == 1 {
                [0, 1, 2, 3].map(|w| (a[w] + b[w]) * 0.5)
            } else {
                a
            };
            let face_transfer = t
                .neighbours
                .iter()
                .find(|n| n.offset == *axis)
                .map_or(DVec4::ZERO, |n| n.transfer);
            let b = geometry.blocking(blocker, b, face_transfer, *axis);
            let blocking = (1.0 - use_blocking * b).clamp(0.0, 1.0);
            for f in axis_faces {
                let flux = f.solid_angle * l.dot(sh::basis(f.direction)).max(0.0) * blocking;
                dst += sh::cosine_lobe(f.normal) * (flux / std::f64::consts::PI);
            }
        }
        dst
    })
}

/// Total energy (integral over the sphere, summed over cells) of a lattice.
pub fn energy(cells: &[DVec4]) -> f64 {
    cells.iter().map(|c| sh::energy(*c)).sum()
}

/// The flux a 6-neighbour step moves out of the cells of `src` into cells inside the lattice,
/// face by face (the scheme's own bookkeeping, independent of its re-projection).
pub fn face_fraction_flux(lattice: &Lattice, src: &[DVec4], faces: &FaceScheme) -> f64 {
    let d = lattice.dims.as_ivec3();
    let mut total = 0.0;
    for z in 0..d.z {
        for y in 0..d.y {
            for x in 0..d.x {
                let c = IVec3::new(x, y, z);
                let l = src[lattice.index(c.as_uvec3())];
                for (axis, axis_faces) in &faces.axes {
                    if lattice.checked(c + *axis).is_none() {
                        continue;
                    }
                    total += axis_faces
                        .iter()
                        .map(|f| f.solid_angle * l.dot(sh::basis(f.direction)).max(0.0))
                        .sum::<f64>();
                }
            }
        }
    }
    total
}
