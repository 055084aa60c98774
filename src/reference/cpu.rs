//! The path tracer's estimator on the CPU, step for step as in pathtrace.comp, with the same
//! random numbers; tests compare it with the GPU on small images.

use glam::{Vec2, Vec3, Vec4};

use super::rng::random_float;
use super::{
    Bounces, RUSSIAN_ROULETTE_START, ReferenceImages, ReferenceSettings, inverse_view_projection,
    ray_epsilon,
};
use crate::imageio::HdrImage;
use crate::scene::bvh::Bvh;
use crate::scene::{Light, Scene};

/// Irradiance factor and direction toward a light, as `light_incidence` in lights.glsl.
fn light_incidence(light: &Light, p: Vec3) -> (Vec3, Vec3, f32) {
    let d = light.position - p;
    let distance = d.length_squared().max(1e-20).sqrt();
    let to_light = d / distance;
    let e = light.intensity() * (light.profile(-to_light) / (distance * distance));
    (e, to_light, distance)
}

/// As `orthonormal_basis` + `sample_cosine_hemisphere` in sampling.glsl.
fn sample_cosine_hemisphere(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let c = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    let b = Vec3::new(c, s + n.y * n.y * a, -n.y);
    let r = u1.sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

/// Render with the CPU estimator (single-threaded; meant for small images).
pub fn render(scene: &Scene, settings: &ReferenceSettings) -> ReferenceImages {
    let bvh = Bvh::build(&scene.mesh);
    let (w, h) = (settings.width, settings.height);
    let inv = inverse_view_projection(scene, w, h);
    let eps = ray_epsilon(scene);
    let mut direct = vec![[0.0f32; 3]; (w * h) as usize];
    let mut indirect = vec![[0.0f32; 3]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let pixel_index = y * w + x;
            let (d, i) = pixel(scene, &bvh, settings, inv, eps, x, y, pixel_index);
            let n = settings.spp.max(1) as f32;
            direct[pixel_index as usize] = (d / n).to_array();
            indirect[pixel_index as usize] = (i / n).to_array();
        }
    }
    ReferenceImages {
        direct: HdrImage::new(w, h, direct),
        indirect: HdrImage::new(w, h, indirect),
    }
}

#[allow(clippy::too_many_arguments)]
fn pixel(
    scene: &Scene,
    bvh: &Bvh,
    settings: &ReferenceSettings,
    inv: glam::Mat4,
    eps: f32,
    x: u32,
    y: u32,
    pixel_index: u32,
) -> (Vec3, Vec3) {
    let (w, h) = (settings.width as f32, settings.height as f32);
    let seed = settings.seed;
    let mesh = &scene.mesh;
    let has_emission = scene
        .materials
        .iter()
        .any(|m| m.emission.max_element() > 0.0);
    let mut direct = Vec3::ZERO;
    let mut indirect = Vec3::ZERO;
    for sample in 0..settings.spp {
        let rand = |dim: u32| random_float(seed, pixel_index, sample, dim);
        let jitter = Vec2::new(rand(0), rand(1));
        let ndc = (Vec2::new(x as f32, y as f32) + jitter) / Vec2::new(w, h) * 2.0 - 1.0;
        let near = inv * Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let mut dir = (far.truncate() / far.w - near.truncate() / near.w).normalize();
        let mut origin = scene.camera.position;
        let mut throughput = Vec3::ONE;
        for depth in 0..crate::shader_shared::REFERENCE_MAX_DEPTH {
            let Some(hit) = bvh.intersect(mesh, origin, dir, eps, 1e30) else {
                break;
            };
            let t = hit.triangle;
            let [a, b, c] = mesh.triangle(t);
            let p = origin + dir * hit.t;
            let mut ng = (b - a).cross(c - a).normalize();
            if ng.dot(dir) > 0.0 {
                ng = -ng;
            }
            let mut ns = mesh.shading_normal(t, hit.uv);
            if ns.dot(ng) < 0.0 {
                ns = -ns;
            }
            let m = &scene.materials[mesh.materials[t] as usize];
            let emitted = throughput * m.emission;
            if depth <= 1 {
                direct += emitted;
            } else {
                indirect += emitted;
            }
            if let Bounces::Limited(max) = settings.bounces
                && depth > max
            {
                break;
            }
            let shade_origin = p + ng * eps;
            for light in &scene.lights {
                let (e, to_light, distance) = light_incidence(light, p);
                let cos_theta = ns.dot(to_light);
                if cos_theta <= 0.0 || ng.dot(to_light) <= 0.0 || e == Vec3::ZERO {
                    continue;
                }
                if bvh
                    .intersect(mesh, shade_origin, to_light, 0.0, distance - 2.0 * eps)
                    .is_some()
                {
                    continue;
                }
                let reflected = throughput * m.albedo * std::f32::consts::FRAC_1_PI * e * cos_theta;
                if depth == 0 {
                    direct += reflected;
                } else {
                    indirect += reflected;
                }
            }
            // The bounce out of the last allowed reflection only looks for emission.
            if settings.bounces == Bounces::Limited(depth) && !has_emission {
                break;
            }
            let dim = 2 + 3 * depth;
            let next = sample_cosine_hemisphere(ns, rand(dim), rand(dim + 1));
            if next.dot(ng) <= 0.0 {
                break;
            }
            throughput *= m.albedo;
            if settings.bounces == Bounces::Unlimited && depth >= RUSSIAN_ROULETTE_START {
                let survive = throughput.max_element().min(0.95);
                if rand(dim + 2) >= survive {
                    break;
                }
                throughput /= survive;
            }
            if throughput == Vec3::ZERO {
                break;
            }
            origin = shade_origin;
            dir = next;
        }
    }
    (direct, indirect)
}
