//! The f64 reference of the method's core: the classical radiosity system on the same elements
//! as the GPU, solved by Gauss–Seidel, with the same disc-approximation form factor (spec 004
//! §1) between element centroids and visibility by ray casting instead of an item buffer.
//! Punctual lights deliver I(ω)·cos θ / r² to every element they see.

use glam::{DVec3, Vec3};

use super::elements::Elements;
use crate::scene::Scene;
use crate::scene::bvh::Bvh;

/// Irradiance per element (W/m² per channel), split as the display uses it.
#[derive(Clone, Debug, Default)]
pub struct Solution {
    /// From emitters and punctual lights, unreflected.
    pub direct: Vec<DVec3>,
    /// From light reflected once or more.
    pub indirect: Vec<DVec3>,
    /// Gauss–Seidel sweeps run.
    pub sweeps: u32,
}

/// The disc-approximation form factor from an element at `x` (normal `nx`) to a disc of area
/// `a` at `s` facing `ns`: a·cos θs·cos θx / (π r² + a), 0 behind either.
pub fn disc_form_factor(x: DVec3, nx: DVec3, s: DVec3, ns: DVec3, a: f64) -> f64 {
    let v = x - s;
    let r2 = v.length_squared();
    if r2 <= 0.0 {
        return 0.0;
    }
    let r = r2.sqrt();
    let cos_s = ns.dot(v) / r;
    let cos_x = -nx.dot(v) / r;
    if cos_s <= 0.0 || cos_x <= 0.0 {
        return 0.0;
    }
    a * cos_s * cos_x / (std::f64::consts::PI * r2 + a)
}

/// Solve to a relative change below `tolerance` per sweep (or `max_sweeps`).
pub fn solve(scene: &Scene, elements: &Elements, tolerance: f64, max_sweeps: u32) -> Solution {
    let bvh = Bvh::build(&scene.mesh);
    let (lo, hi) = scene.mesh.bounds();
    let offset = 1e-4 * f64::from((hi - lo).length());
    let valid: Vec<usize> = (0..elements.elements.len())
        .filter(|&i| elements.elements[i].area > 0.0)
        .collect();
    let normal = |i: usize| {
        elements.surfaces[elements.elements[i].surface as usize]
            .normal
            .as_dvec3()
    };
    let position = |i: usize| elements.elements[i].position.as_dvec3();
    let visible = |i: usize, j: usize| {
        let from = (position(i) + normal(i) * offset).as_vec3();
        let to = (position(j) + normal(j) * offset).as_vec3();
        let d = to - from;
        let length = d.length();
        length <= 0.0
            || !bvh.occluded(from, d / length, 0.0, length)
    };
    // Row i: (j, F from i to j's disc).
    let rows: Vec<Vec<(usize, f64)>> = valid
        .iter()
        .map(|&i| {
            valid
                .iter()
                .filter(|&&j| elements.elements[j].surface != elements.elements[i].surface)
                .filter_map(|&j| {
                    let a = f64::from(elements.elements[j].area);
                    let f = disc_form_factor(position(i), normal(i), position(j), normal(j), a);
                    (f > 0.0 && visible(i, j)).then_some((j, f))
                })
                .collect()
        })
        .collect();
    let n = elements.elements.len();
    let mut direct = vec![DVec3::ZERO; n];
    for (&i, row) in valid.iter().zip(&rows) {
        let emitted: DVec3 = row
            .iter()
            .map(|&(j, f)| {
                elements.surfaces[elements.elements[j].surface as usize]
                    .emission
                    .as_dvec3()
                    * f
            })
            .sum();
        let x = position(i) + normal(i) * offset;
        let punctual: DVec3 = scene
            .lights
            .iter()
            .filter(|light| {
                let to = light.position;
                let d = to - x.as_vec3();
                let length = d.length();
                length > 0.0
                    && !bvh.occluded(x.as_vec3(), d / length, 0.0, length)
            })
            .map(|light| {
                light
                    .irradiance_at(position(i).as_vec3(), normal(i).as_vec3())
                    .as_dvec3()
            })
            .sum();
        direct[i] = emitted + punctual;
    }
    let albedo = |j: usize| elements.elements[j].albedo.as_dvec3();
    let mut total = direct.clone();
    let mut sweeps = 0;
    while sweeps < max_sweeps {
        sweeps += 1;
        let mut change: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for (&i, row) in valid.iter().zip(&rows) {
            let gathered: DVec3 = row.iter().map(|&(j, f)| albedo(j) * total[j] * f).sum();
            let next = direct[i] + gathered;
            change = change.max((next - total[i]).abs().max_element());
            scale = scale.max(next.max_element());
            total[i] = next;
        }
        if change <= tolerance * scale.max(f64::MIN_POSITIVE) {
            break;
        }
    }
    let indirect = total.iter().zip(&direct).map(|(t, d)| *t - *d).collect();
    Solution {
        direct,
        indirect,
        sweeps,
    }
}

/// Total power (W, mean over channels) an irradiance field delivers to the elements.
pub fn received_power(elements: &Elements, irradiance: &[DVec3]) -> f64 {
    elements
        .elements
        .iter()
        .zip(irradiance)
        .map(|(e, h)| f64::from(e.area) * h.element_sum() / 3.0)
        .sum()
}

/// Emitted power of every emitting surface plus every punctual light's flux (mean over
/// channels).
pub fn emitted_power(scene: &Scene, elements: &Elements) -> f64 {
    let surfaces: f64 = elements
        .surfaces
        .iter()
        .map(|s| s.area * f64::from(s.emission.element_sum()) / 3.0)
        .sum();
    let lights: f64 = scene
        .lights
        .iter()
        .map(|l| f64::from(l.flux) * f64::from((l.color * Vec3::ONE).element_sum()) / 3.0)
        .sum();
    surfaces + lights
}
