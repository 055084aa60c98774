//! LightWave's gather on the CPU in f64 (the reference the GPU gather is tested against), and
//! the gain that puts the thesis's unit-less indirect term into watts: fitted by least squares
//! to a path-traced image, with exact visibility toward the VPLs that cast indirect shadows.

use glam::{DVec3, Vec2, Vec3};

use super::rig::{Rig, Vpl};
use crate::imageio::HdrImage;
use crate::scene::bvh::Bvh;
use crate::scene::{Light, Scene};

/// The thesis's widened emission lobe (spec 002 §2.4): (cos θ + 0.5) / 1.5 clamped to [0, 1],
/// 1 on the VPL's axis, 1/3 at 90°, 0 from 120°.
pub fn lobe(cos_theta: f64) -> f64 {
    ((cos_theta + 0.5) / 1.5).clamp(0.0, 1.0)
}

/// The thesis's indirect term at a point with unit normal `normal`, without albedo or light
/// (eq 4.5 without its specular part): (1/N) Σ_j w_j sat(n·ω_j) lobe(n_j·(-ω_j)), ω_j the unit
/// direction from the point to VPL j. A VPL at the point itself adds nothing.
pub fn gather(vpls: &[Vpl], point: DVec3, normal: DVec3) -> f64 {
    if vpls.is_empty() {
        return 0.0;
    }
    let sum: f64 = vpls
        .iter()
        .filter_map(|vpl| {
            let to_vpl = vpl.position - point;
            let length = to_vpl.length();
            (length > 1e-12).then(|| {
                let omega = to_vpl / length;
                vpl.weight * normal.dot(omega).clamp(0.0, 1.0) * lobe(-vpl.direction.dot(omega))
            })
        })
        .sum();
    sum / vpls.len() as f64
}

/// The normal the per-vertex gather uses at each vertex of `mesh`: its shading normal, or where
/// it has none the normalised sum of its triangles' area-weighted face normals (+Y if they
/// cancel).
pub fn gather_normals(mesh: &crate::scene::Mesh) -> Vec<Vec3> {
    let mut faces = vec![Vec3::ZERO; mesh.positions.len()];
    for corners in &mesh.indices {
        let [a, b, c] = corners.map(|i| mesh.positions[i as usize]);
        let area_normal = (b - a).cross(c - a);
        for i in corners {
            faces[*i as usize] += area_normal;
        }
    }
    mesh.normals
        .iter()
        .zip(faces)
        .map(|(&shading, face)| {
            if shading != Vec3::ZERO {
                shading
            } else {
                face.try_normalize().unwrap_or(Vec3::Y)
            }
        })
        .collect()
}

/// A light's axis as the rig uses it: a spot's or an area sample's, straight down for a point
/// light (the thesis's light looks down; src/scene/gpu.rs gives point lights the same axis).
pub fn rig_axis(light: &Light) -> DVec3 {
    light.axis().map_or(DVec3::NEG_Y, |a| a.as_dvec3().normalize())
}

/// What the gain fit sees at one pixel: its albedo, and per light its unit-gain indirect
/// irradiance factor I_l·S_l·V_l (peak intensity times gather times visibility).
struct PixelTerms {
    albedo: DVec3,
    irradiance: DVec3,
}

/// The least-squares gain G minimising Σ (albedo/π · G · Σ_l I_l S_l V_l - truth)² over every
/// pixel and channel of `truth` (the path-traced indirect light of the scene camera), where
/// V_l is the fraction of the light's shadow-casting VPLs (`shadow_set`) a pixel sees, by ray
/// casting (1 with none). 0 when nothing is lit.
pub fn fit_gain(
    scene: &Scene,
    bvh: &Bvh,
    lights: &[Light],
    rig: &Rig,
    shadow_set: &[u32],
    truth: &HdrImage,
) -> f64 {
    let rigs: Vec<(Vec<Vpl>, DVec3)> = lights
        .iter()
        .map(|l| {
            (
                rig.vpls(l.position.as_dvec3(), rig_axis(l)),
                l.intensity().as_dvec3(),
            )
        })
        .collect();
    let epsilon = crate::reference::ray_epsilon(scene);
    let (mut numerator, mut denominator) = (0.0f64, 0.0f64);
    for y in 0..truth.height {
        for x in 0..truth.width {
            let Some(terms) = pixel_terms(scene, bvh, &rigs, shadow_set, epsilon, (x, y), truth)
            else {
                continue;
            };
            let t = truth.pixels[(y * truth.width + x) as usize];
            let predicted = terms.albedo * terms.irradiance / std::f64::consts::PI;
            for c in 0..3 {
                numerator += predicted[c] * f64::from(t[c]);
                denominator += predicted[c] * predicted[c];
            }
        }
    }
    if denominator > 0.0 {
        numerator / denominator
    } else {
        0.0
    }
}

fn pixel_terms(
    scene: &Scene,
    bvh: &Bvh,
    rigs: &[(Vec<Vpl>, DVec3)],
    shadow_set: &[u32],
    epsilon: f32,
    (x, y): (u32, u32),
    truth: &HdrImage,
) -> Option<PixelTerms> {
    let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
    let dir = scene.camera.ray_direction(pixel, truth.width, truth.height);
    let hit = bvh.intersect(scene.camera.position, dir, epsilon, f32::INFINITY)?;
    let point = scene.camera.position + dir * hit.t;
    let mut normal = scene.mesh.shading_normal(hit.triangle, hit.uv);
    if normal.dot(dir) > 0.0 {
        normal = -normal;
    }
    let mut irradiance = DVec3::ZERO;
    for (vpls, intensity) in rigs {
        let s = gather(vpls, point.as_dvec3(), normal.as_dvec3());
        if s == 0.0 {
            continue;
        }
        let visible = if shadow_set.is_empty() {
            1.0
        } else {
            let lit = shadow_set
                .iter()
                .filter(|&&j| sees(bvh, point + normal * epsilon, vpls[j as usize].position.as_vec3(), epsilon))
                .count();
            lit as f64 / shadow_set.len() as f64
        };
        irradiance += *intensity * (s * visible);
    }
    Some(PixelTerms {
        albedo: scene.albedo(hit.triangle, hit.uv).as_dvec3(),
        irradiance,
    })
}

/// Whether `to` is unoccluded from `from`.
fn sees(bvh: &Bvh, from: Vec3, to: Vec3, epsilon: f32) -> bool {
    let d = to - from;
    let length = d.length();
    length <= epsilon || !bvh.occluded(from, d / length, epsilon, length - epsilon)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lobe_spans_240_degrees() {
        assert_eq!(lobe(1.0), 1.0);
        assert!((lobe(0.0) - 1.0 / 3.0).abs() < 1e-15);
        assert_eq!(lobe((120f64).to_radians().cos() - 1e-12), 0.0);
        assert!(lobe((119f64).to_radians().cos()) > 0.0);
    }

    #[test]
    fn one_vpl_straight_above_gives_its_weight() {
        let vpl = Vpl {
            position: DVec3::new(0.0, 2.0, 0.0),
            direction: DVec3::NEG_Y,
            weight: 0.8,
        };
        assert!((gather(&[vpl], DVec3::ZERO, DVec3::Y) - 0.8).abs() < 1e-15);
        // Behind the surface: nothing; at the point itself: nothing.
        assert_eq!(gather(&[vpl], DVec3::ZERO, DVec3::NEG_Y), 0.0);
        assert_eq!(gather(&[vpl], vpl.position, DVec3::Y), 0.0);
        // Seen from the side at 90° off the VPL's axis: the lobe's 1/3 times cos 45°.
        let side = gather(&[vpl], DVec3::new(2.0, 2.0, 0.0), DVec3::new(-1.0, 1.0, 0.0).normalize());
        assert!((side - 0.8 / 3.0 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12, "{side}");
    }
}
