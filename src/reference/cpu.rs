//! The path tracer's estimator on the CPU, step for step as in pathtrace.comp (punctual lights
//! and emitters by next-event estimation, emitter hits by bounces, combined by multiple
//! importance sampling), with the same random numbers. Tests hold it to the GPU's; `--tracer
//! auto` renders references with it when the Vulkan device is itself a CPU.

use std::sync::atomic::{AtomicU32, Ordering};

use glam::{DVec3, Vec2, Vec3, Vec4};

use super::rng::random_float;
use super::{
    Bounces, RUSSIAN_ROULETTE_START, ReferenceImages, ReferenceSettings, SAMPLES_PER_BATCH,
    Strategy, inverse_view_projection, mean_image, ray_epsilon,
};
use crate::scene::brdf;
use crate::scene::bvh::Bvh;
use crate::scene::emitters::Emitters;
use crate::scene::{Light, Scene};
use crate::shader_shared::REFERENCE_EMITTER_DIM;

/// Irradiance factor and direction toward a light, as `light_incidence` in lights.glsl.
fn light_incidence(light: &Light, p: Vec3) -> (Vec3, Vec3, f32) {
    let d = light.position - p;
    let distance = d.length_squared().max(1e-20).sqrt();
    let to_light = d / distance;
    let e = light.intensity() * (light.profile(-to_light) / (distance * distance));
    (e, to_light, distance)
}

/// As `orthonormal_basis` in sampling.glsl: (tangent, bitangent, n).
fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3, Vec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let c = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    let b = Vec3::new(c, s + n.y * n.y * a, -n.y);
    (t, b, n)
}

/// As `sample_cosine_hemisphere` in sampling.glsl.
pub(crate) fn sample_cosine_hemisphere(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let (t, b, _) = orthonormal_basis(n);
    let r = u1.sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

/// Power heuristic weight of a strategy of density `a` against one of density `b`.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    a2 / (a2 + b * b).max(1e-30)
}

/// Render with the CPU estimator on `threads` threads (rows shared out as threads ask for
/// them), in batches of [`SAMPLES_PER_BATCH`] samples, every sample added to its pixel's f64
/// sums (the GPU sums a batch in f32 before the host adds it in f64). `progress(done, total)`
/// follows the samples. The image does not depend on the thread count: each pixel's samples
/// are its own, summed in one order.
pub fn render(
    scene: &Scene,
    settings: &ReferenceSettings,
    threads: usize,
    mut progress: impl FnMut(u32, u32),
) -> anyhow::Result<ReferenceImages> {
    let bvh = Bvh::build(&scene.mesh);
    let emitters = Emitters::of(scene);
    let (w, h) = (settings.width, settings.height);
    let inv = inverse_view_projection(scene, w, h);
    let eps = ray_epsilon(scene);
    let mut sums = vec![[DVec3::ZERO; 2]; (w * h) as usize];
    let mut done = 0;
    while done < settings.spp {
        let samples = done..(done + SAMPLES_PER_BATCH).min(settings.spp);
        let next_row = AtomicU32::new(0);
        let (tx, rx) = std::sync::mpsc::channel::<(u32, Vec<[DVec3; 2]>)>();
        std::thread::scope(|threads_scope| {
            for _ in 0..threads.max(1) {
                let tx = tx.clone();
                let (bvh, emitters, next_row, samples) = (&bvh, &emitters, &next_row, &samples);
                threads_scope.spawn(move || {
                    loop {
                        let y = next_row.fetch_add(1, Ordering::Relaxed);
                        if y >= h {
                            break;
                        }
                        let row = (0..w)
                            .map(|x| {
                                let at = Pixel {
                                    x,
                                    y,
                                    index: y * w + x,
                                };
                                pixel(
                                    scene,
                                    (bvh, emitters),
                                    settings,
                                    (inv, eps),
                                    at,
                                    samples.clone(),
                                )
                            })
                            .collect();
                        if tx.send((y, row)).is_err() {
                            break;
                        }
                    }
                });
            }
            drop(tx);
            for (y, row) in rx {
                let first = (y * w) as usize;
                for (sum, add) in sums[first..first + w as usize].iter_mut().zip(row) {
                    sum[0] += add[0];
                    sum[1] += add[1];
                }
            }
        });
        done = samples.end;
        progress(done, settings.spp);
    }
    let part = |k: usize| sums.iter().map(move |s| s[k].to_array());
    Ok(ReferenceImages {
        direct: mean_image(part(0), settings)?,
        indirect: mean_image(part(1), settings)?,
    })
}

/// A pixel of the image: its column, row and index in row-major order.
#[derive(Clone, Copy)]
struct Pixel {
    x: u32,
    y: u32,
    index: u32,
}

/// The summed direct and indirect estimates of one pixel over `samples`.
fn pixel(
    scene: &Scene,
    (bvh, emitters): (&Bvh, &Emitters),
    settings: &ReferenceSettings,
    (inv, eps): (glam::Mat4, f32),
    Pixel {
        x,
        y,
        index: pixel_index,
    }: Pixel,
    samples: std::ops::Range<u32>,
) -> [DVec3; 2] {
    let (w, h) = (settings.width as f32, settings.height as f32);
    let seed = settings.seed;
    let mesh = &scene.mesh;
    let has_emission = scene
        .materials
        .iter()
        .any(|m| m.emission.max_element() > 0.0);
    let mut sums = [DVec3::ZERO; 2];
    for sample in samples {
        let mut direct = Vec3::ZERO;
        let mut indirect = Vec3::ZERO;
        let rand = |dim: u32| random_float(seed, pixel_index, sample, dim);
        let jitter = Vec2::new(rand(0), rand(1));
        let ndc = (Vec2::new(x as f32, y as f32) + jitter) / Vec2::new(w, h) * 2.0 - 1.0;
        let near = inv * Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let mut dir = (far.truncate() / far.w - near.truncate() / near.w).normalize();
        let mut origin = scene.camera.position;
        let mut throughput = Vec3::ONE;
        // Density (solid angle) of the bounce that produced `dir`; 0 for camera rays.
        let mut bounce_pdf = 0.0f32;
        let strategy = settings.strategy;
        let sampled = !emitters.triangles.is_empty();
        for depth in 0..crate::shader_shared::REFERENCE_MAX_DEPTH {
            let Some(hit) = bvh.intersect(origin, dir, eps, 1e30) else {
                break;
            };
            let t = hit.triangle;
            let [a, b, c] = mesh.triangle(t);
            let p = origin + dir * hit.t;
            let mut ng = (b - a).cross(c - a).normalize();
            let cos_emit = -ng.dot(dir);
            if ng.dot(dir) > 0.0 {
                ng = -ng;
            }
            let mut ns = mesh.shading_normal(t, hit.uv);
            if ns.dot(ng) < 0.0 {
                ns = -ns;
            }
            let m = &scene.materials[mesh.materials[t] as usize];
            let albedo = scene.albedo(t, hit.uv);
            let (specular, roughness) = (m.specular, m.roughness);
            let glossy = brdf::glossy_share(albedo, specular);
            let view = -dir;
            if (cos_emit > 0.0 || m.two_sided) && m.emission.max_element() > 0.0 {
                let weight = if depth > 0 && sampled {
                    let light_pdf =
                        emitters.area_pdf(m) * hit.t * hit.t / cos_emit.abs().max(1e-20);
                    match strategy {
                        Strategy::Light => 0.0,
                        Strategy::Bsdf => 1.0,
                        Strategy::Mis => power_heuristic(bounce_pdf, light_pdf),
                    }
                } else {
                    1.0
                };
                let emitted = throughput * m.emission * weight;
                if depth <= 1 {
                    direct += emitted;
                } else {
                    indirect += emitted;
                }
            }
            if let Bounces::Limited(max) = settings.bounces
                && depth > max
            {
                break;
            }
            let shade_origin = p + ng * eps;
            for light in &scene.lights {
                let (e, to_light, _) = light_incidence(light, p);
                let cos_theta = ns.dot(to_light);
                if cos_theta <= 0.0 || ng.dot(to_light) <= 0.0 || e == Vec3::ZERO {
                    continue;
                }
                // The shadow ray leaves the offset origin aimed at the light itself.
                let offset = light.position - shade_origin;
                let reach = offset.length();
                if bvh.occluded(shade_origin, offset / reach, 0.0, reach - eps) {
                    continue;
                }
                let mut reflected =
                    throughput * albedo * std::f32::consts::FRAC_1_PI * e * cos_theta;
                if glossy > 0.0 {
                    reflected +=
                        throughput * e * brdf::glossy_cos(specular, roughness, ns, to_light, view);
                }
                if depth == 0 {
                    direct += reflected;
                } else {
                    indirect += reflected;
                }
            }
            if sampled && strategy != Strategy::Bsdf {
                let edim = REFERENCE_EMITTER_DIM + 3 * depth;
                let chosen = emitters.triangles[emitters.pick(rand(edim))] as usize;
                let [ea, eb, ec] = mesh.triangle(chosen);
                let su = rand(edim + 1).sqrt();
                let v2 = rand(edim + 2);
                let q = ea * (1.0 - su) + eb * (su * (1.0 - v2)) + ec * (su * v2);
                let en = (eb - ea).cross(ec - ea).normalize();
                let em = &scene.materials[mesh.materials[chosen] as usize];
                let d = q - shade_origin;
                let dist2 = d.dot(d);
                let dist = dist2.sqrt();
                let wi = d / dist;
                let cos_s = ns.dot(wi);
                let mut cos_e = -en.dot(wi);
                if em.two_sided {
                    cos_e = cos_e.abs();
                }
                if cos_s > 0.0
                    && ng.dot(wi) > 0.0
                    && cos_e > 0.0
                    && !bvh.occluded(shade_origin, wi, 0.0, dist - eps)
                {
                    let light_pdf = emitters.area_pdf(em) * dist2 / cos_e;
                    let bsdf_pdf = if glossy > 0.0 {
                        (1.0 - glossy) * cos_s * std::f32::consts::FRAC_1_PI
                            + glossy * brdf::glossy_pdf(roughness, ns, wi, view)
                    } else {
                        cos_s * std::f32::consts::FRAC_1_PI
                    };
                    let weight = if strategy == Strategy::Mis {
                        power_heuristic(light_pdf, bsdf_pdf)
                    } else {
                        1.0
                    };
                    let mut reflected = throughput
                        * albedo
                        * std::f32::consts::FRAC_1_PI
                        * em.emission
                        * (cos_s * weight / light_pdf);
                    if glossy > 0.0 {
                        reflected += throughput
                            * brdf::glossy_cos(specular, roughness, ns, wi, view)
                            * em.emission
                            * (weight / light_pdf);
                    }
                    if depth == 0 {
                        direct += reflected;
                    } else {
                        indirect += reflected;
                    }
                }
            }
            // The bounce out of the last allowed reflection only looks for emission.
            if settings.bounces == Bounces::Limited(depth) && !has_emission {
                break;
            }
            let dim = 2 + 3 * depth;
            let (u1, u2) = (rand(dim), rand(dim + 1));
            let next = if u1 < glossy {
                brdf::sample_glossy(roughness, orthonormal_basis(ns), view, u1 / glossy, u2)
            } else {
                let u1 = if glossy > 0.0 {
                    (u1 - glossy) / (1.0 - glossy)
                } else {
                    u1
                };
                sample_cosine_hemisphere(ns, u1, u2)
            };
            if next.dot(ng) <= 0.0 {
                break;
            }
            if glossy > 0.0 {
                // One sample of the mixture: the whole BRDF over the mixture's density.
                let cos_n = ns.dot(next);
                if cos_n <= 0.0 {
                    break;
                }
                bounce_pdf = (1.0 - glossy) * cos_n * std::f32::consts::FRAC_1_PI
                    + glossy * brdf::glossy_pdf(roughness, ns, next, view);
                // A normal facing away from the view (shading normals) can be drawn where the
                // density is 0 when the lobe is all there is.
                if bounce_pdf <= 0.0 {
                    break;
                }
                throughput *= (albedo * std::f32::consts::FRAC_1_PI * cos_n
                    + brdf::glossy_cos(specular, roughness, ns, next, view))
                    / bounce_pdf;
            } else {
                bounce_pdf = ns.dot(next) * std::f32::consts::FRAC_1_PI;
                throughput *= albedo;
            }
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
        sums[0] += direct.as_dvec3();
        sums[1] += indirect.as_dvec3();
    }
    sums
}
