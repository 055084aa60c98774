//! The emissive triangles of a scene, sampled by power for next-event estimation: a triangle is
//! chosen with probability power / total power, then a point on it uniformly. The power of a
//! triangle is its mean emitted radiance over RGB times its area times π (one-sided) or 2π
//! (two-sided), so the density per unit area of the chosen point is
//! π·sides·mean(Le) / total power, the same for every point of one material: a BSDF-sampled hit
//! on an emitter finds its light-sampling density from its material alone (MIS).

use glam::Vec3;

use crate::scene::{Light, LightKind, Material, Scene};

/// Emitters in the order the GPU buffer holds them, with their cumulative distribution.
#[derive(Clone, Debug, Default)]
pub struct Emitters {
    /// Mesh triangle index of each emitter.
    pub triangles: Vec<u32>,
    /// Cumulative probability up to and including each emitter (the last is 1).
    pub cdf: Vec<f32>,
    /// Total emitted power (W, mean over RGB).
    pub power: f64,
}

/// Mean emitted radiance over RGB times the faces it leaves: the power per area / π.
pub fn radiant_weight(m: &Material) -> f64 {
    let sides = if m.two_sided { 2.0 } else { 1.0 };
    sides * f64::from(m.emission.element_sum()) / 3.0
}

impl Emitters {
    pub fn of(scene: &Scene) -> Emitters {
        let mesh = &scene.mesh;
        let mut triangles = Vec::new();
        let mut powers = Vec::new();
        for t in 0..mesh.triangle_count() {
            let weight = radiant_weight(&scene.materials[mesh.materials[t] as usize]);
            if weight <= 0.0 {
                continue;
            }
            let [a, b, c] = mesh.triangle(t).map(Vec3::as_dvec3);
            let area = 0.5 * (b - a).cross(c - a).length();
            let power = std::f64::consts::PI * weight * area;
            if power > 0.0 {
                triangles.push(t as u32);
                powers.push(power);
            }
        }
        let total: f64 = powers.iter().sum();
        let mut running = 0.0;
        let mut cdf: Vec<f32> = powers
            .iter()
            .map(|p| {
                running += p;
                (running / total) as f32
            })
            .collect();
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Emitters {
            triangles,
            cdf,
            power: total,
        }
    }

    /// The emitter the uniform number `u` picks (as the shader's binary search).
    pub fn pick(&self, u: f32) -> usize {
        let (mut lo, mut hi) = (0, self.cdf.len().saturating_sub(1));
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.cdf[mid] < u {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// Density per unit area of sampling a point on an emitter of material `m`.
    pub fn area_pdf(&self, m: &Material) -> f32 {
        if self.power > 0.0 {
            (std::f64::consts::PI * radiant_weight(m) / self.power) as f32
        } else {
            0.0
        }
    }
}

/// Radical inverse in base 2 (van der Corput): the second coordinate of a Hammersley point.
fn radical_inverse(mut i: u32) -> f32 {
    i = i.rotate_right(16);
    i = ((i & 0x5555_5555) << 1) | ((i & 0xAAAA_AAAA) >> 1);
    i = ((i & 0x3333_3333) << 2) | ((i & 0xCCCC_CCCC) >> 2);
    i = ((i & 0x0F0F_0F0F) << 4) | ((i & 0xF0F0_F0F0) >> 4);
    i = ((i & 0x00FF_00FF) << 8) | ((i & 0xFF00_FF00) >> 8);
    i as f32 * (1.0 / 4_294_967_296.0)
}

/// The scene's emissive triangles as `count` cosine-lobed lights, which is how the rasteriser
/// and the RSM-based methods see area lights: sample k picks an emitter by power at the
/// stratified number (k + ½)/count and a point on it (Hammersley), and carries 1/count of the
/// total power, facing the emitting side (two-sided emitters get a light per side, half each).
/// Lights sit `offset` off the surface so they do not shadow themselves.
pub fn area_light_samples(scene: &Scene, count: u32, offset: f32) -> Vec<Light> {
    let emitters = Emitters::of(scene);
    if emitters.triangles.is_empty() || count == 0 {
        return Vec::new();
    }
    let mesh = &scene.mesh;
    let share = (emitters.power / f64::from(count)) as f32;
    let mut lights = Vec::new();
    for k in 0..count {
        let t = emitters.triangles[emitters.pick((k as f32 + 0.5) / count as f32)] as usize;
        let [a, b, c] = mesh.triangle(t);
        let su = ((k as f32 + 0.5) / count as f32 * 7.0).fract().sqrt();
        let v = radical_inverse(k);
        let q = a * (1.0 - su) + b * (su * (1.0 - v)) + c * (su * v);
        let n = mesh.face_normal(t);
        let m = &scene.materials[mesh.materials[t] as usize];
        let mean = m.emission.element_sum() / 3.0;
        let sides: &[f32] = if m.two_sided { &[1.0, -1.0] } else { &[1.0] };
        for &side in sides {
            let direction = n * side;
            lights.push(Light {
                position: q + direction * offset,
                kind: LightKind::Cosine { direction },
                flux: share / sides.len() as f32,
                color: m.emission / mean,
            });
        }
    }
    lights
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Camera, Mesh};

    fn scene(emissions: &[(f32, bool, f32)]) -> Scene {
        let mut mesh = Mesh::default();
        let mut materials = Vec::new();
        for (k, &(le, two_sided, size)) in emissions.iter().enumerate() {
            let o = Vec3::new(k as f32 * 10.0, 0.0, 0.0);
            mesh.push_triangle(
                [o, o + Vec3::X * size, o + Vec3::Z * size],
                [Vec3::ZERO; 3],
                k as u32,
            );
            materials.push(Material {
                emission: Vec3::splat(le),
                two_sided,
                ..Material::diffuse(&format!("m{k}"), Vec3::splat(0.5))
            });
        }
        let camera = Camera {
            position: Vec3::new(0.0, 5.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 60.0,
        };
        match Scene::new("e".into(), mesh, materials, vec![], camera) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn triangles_are_chosen_by_power_and_densities_integrate_to_one() {
        // Powers π·1·2·0.5 (two-sided, area 0.5), 0 (dark), π·3·1·2 (one-sided, area 2).
        let s = scene(&[(1.0, true, 1.0), (0.0, false, 1.0), (3.0, false, 2.0)]);
        let e = Emitters::of(&s);
        assert_eq!(e.triangles, vec![0, 2]);
        let p0 = std::f64::consts::PI;
        let p2 = std::f64::consts::PI * 6.0;
        assert!((e.power - (p0 + p2)).abs() < 1e-9);
        assert!((f64::from(e.cdf[0]) - p0 / (p0 + p2)).abs() < 1e-6);
        assert_eq!(e.pick(0.0), 0);
        assert_eq!(e.pick(0.99), 1);
        // ∫ pdf dA over every emitter = 1.
        let total: f64 = [(0usize, 0.5f64), (2, 2.0)]
            .iter()
            .map(|&(m, area)| f64::from(e.area_pdf(&s.materials[m])) * area)
            .sum();
        assert!((total - 1.0).abs() < 1e-6, "{total}");
    }

    #[test]
    fn area_samples_carry_the_emitted_power_toward_the_emitting_side() {
        let s = scene(&[(1.0, true, 1.0), (3.0, false, 2.0)]);
        let e = Emitters::of(&s);
        for count in [1, 4, 16] {
            let lights = area_light_samples(&s, count, 1e-3);
            let power: f64 = lights
                .iter()
                .map(|l| f64::from(l.flux) * f64::from(l.color.element_sum()) / 3.0)
                .sum();
            assert!((power - e.power).abs() < 1e-4 * e.power, "{count}: {power}");
            for l in &lights {
                let LightKind::Cosine { direction } = l.kind else {
                    panic!("a cosine light")
                };
                assert!((direction.length() - 1.0).abs() < 1e-5);
                // Intensity along the axis is Le × (the sample's share of emitting area).
                assert!(l.intensity().is_finite());
            }
        }
        // The one-sided emitter (power 6π of 7π) gets most samples, all facing its winding's
        // normal (x × z = -y).
        let lights = area_light_samples(&s, 16, 1e-3);
        let bright = lights
            .iter()
            .filter(|l| l.position.x > 5.0)
            .inspect(|l| assert_eq!(l.axis(), Some(Vec3::NEG_Y)))
            .count();
        assert!(
            bright >= 12,
            "{bright} of 16 samples on the brighter emitter"
        );
    }
}
