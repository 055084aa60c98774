//! The reference path tracer proven right on lavapipe: the white furnace, a Lambertian plane
//! under a point light, 1/sqrt(spp) convergence, agreement with the raster frame's direct light,
//! agreement with the CPU estimator, determinism and the cache.

mod common;

use glam::{Vec2, Vec3};
use vkgi::imageio::HdrImage;
use vkgi::reference::cache::{self, CacheRecord};
use vkgi::reference::{Bounces, PathTracer, ReferenceImages, ReferenceSettings, Strategy};
use vkgi::scene::Scene;

fn settings(width: u32, height: u32, spp: u32, bounces: Bounces, seed: u32) -> ReferenceSettings {
    ReferenceSettings {
        strategy: Default::default(),
        width,
        height,
        spp,
        bounces,
        seed,
    }
}

fn trace(gpu: &vkgi::gpu::Gpu, scene: &Scene, s: &ReferenceSettings) -> ReferenceImages {
    let mut tracer = PathTracer::new(gpu, scene, s.width, s.height).unwrap();
    tracer.render(gpu, s, |_, _| {}).unwrap()
}

fn rmse(a: &HdrImage, b: &HdrImage) -> f64 {
    let se: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| f64::from(p[c] - q[c]).powi(2)))
        .sum();
    (se / (3 * a.pixels.len()) as f64).sqrt()
}

#[test]
fn white_furnace_matches_the_geometric_series() {
    let gpu = common::gpu();
    let (rho, le) = (0.8f32, 1.0f32);
    let scene = common::furnace(rho, le);
    let cases = [
        (Bounces::Limited(0), le * (1.0 + rho), 8, 512),
        (Bounces::Limited(1), le * (1.0 + rho + rho * rho), 8, 512),
        (Bounces::Unlimited, le / (1.0 - rho), 2, 65536),
    ];
    for (bounces, expected, size, spp) in cases {
        let image = trace(&gpu, &scene, &settings(size, size, spp, bounces, 7)).combined();
        let mut worst = 0.0f32;
        for p in &image.pixels {
            for &v in p {
                let error = (v / expected - 1.0).abs();
                worst = worst.max(error);
                assert!(
                    error < 0.01,
                    "{bounces:?}: radiance {v}, expected {expected}"
                );
            }
        }
        eprintln!(
            "furnace {bounces:?}: expected {expected}, worst relative error {worst:.2e} at {spp} spp"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// The glossy lobe's directional albedo seen at `tilt` radians from the normal, integrated on a
/// fine grid of the hemisphere (independent of how the path tracer samples the lobe).
fn glossy_directional_albedo(specular: f32, roughness: f32, tilt: f32) -> f64 {
    let (n, v) = (Vec3::Z, Vec3::new(tilt.sin(), 0.0, tilt.cos()));
    let steps = 1000;
    let mut sum = 0.0;
    for i in 0..steps {
        let (t0, t1) = (
            std::f64::consts::FRAC_PI_2 * i as f64 / steps as f64,
            std::f64::consts::FRAC_PI_2 * (i + 1) as f64 / steps as f64,
        );
        let theta = 0.5 * (t0 + t1);
        for j in 0..2 * steps {
            let phi = std::f64::consts::PI * (j as f64 + 0.5) / steps as f64;
            let l = glam::DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let area = (t0.cos() - t1.cos()) * std::f64::consts::PI / steps as f64;
            let f =
                vkgi::scene::brdf::glossy_cos(Vec3::splat(specular), roughness, n, l.as_vec3(), v);
            sum += f64::from(f.x) * area;
        }
    }
    sum
}

#[test]
fn a_glossy_white_furnace_reflects_the_lobe_s_directional_albedo() {
    // Uniform radiance le around every point: one reflection adds le * (rho + the glossy lobe's
    // directional albedo), whichever of the mixture's lobes a bounce samples and however MIS
    // weighs emitter samples against bounces.
    let gpu = common::gpu();
    let (rho, le, specular, roughness) = (0.5f32, 1.0f32, 0.4f32, 0.5f32);
    let mut scene = common::furnace(rho, le);
    scene.materials[0] = scene.materials[0]
        .clone()
        .with_gloss(Vec3::splat(specular), roughness);
    // Faces of the level-2 icosphere are within 12 degrees of the ray from its centre.
    let albedo = |tilt_deg: f32| {
        f64::from(rho) + glossy_directional_albedo(specular, roughness, tilt_deg.to_radians())
    };
    let (low, high) = (albedo(12.0).min(albedo(0.0)), albedo(12.0).max(albedo(0.0)));
    eprintln!("glossy furnace: one reflection returns {low:.4}..{high:.4} of le");
    let image = trace(&gpu, &scene, &settings(8, 8, 1024, Bounces::Limited(0), 9)).combined();
    // Per pixel the estimate's standard deviation is about 0.6% here; over 64 pixels, 0.08%.
    let reflected: Vec<f64> = image
        .pixels
        .iter()
        .flatten()
        .map(|&v| f64::from(v / le - 1.0))
        .collect();
    let mean = reflected.iter().sum::<f64>() / reflected.len() as f64;
    eprintln!("glossy furnace: mean reflected {mean:.4} of le");
    assert!(
        mean > low * 0.997 && mean < high * 1.003,
        "mean {mean}, expected {low}..{high}"
    );
    for r in reflected {
        assert!(
            r > low * 0.97 && r < high * 1.03,
            "reflected {r}, expected {low}..{high}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// Radiance of a Lambertian plane under a point light, averaged over a pixel's footprint (16x16 points).
fn analytic_plane_radiance(scene: &Scene, x: u32, y: u32, w: u32, h: u32) -> f32 {
    let light = scene.lights[0];
    let albedo = scene.materials[0].albedo.x;
    let n = 16;
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let px = Vec2::new(
                x as f32 + (i as f32 + 0.5) / n as f32,
                y as f32 + (j as f32 + 0.5) / n as f32,
            );
            let dir = scene.camera.ray_direction(px, w, h);
            let t = -scene.camera.position.y / dir.y;
            let p = scene.camera.position + dir * t;
            sum += albedo / std::f32::consts::PI * light.irradiance_at(p, Vec3::Y).x;
        }
    }
    sum / (n * n) as f32
}

#[test]
fn a_lambertian_plane_under_a_point_light_matches_the_analytic_irradiance() {
    let gpu = common::gpu();
    let scene = common::plane_under_point_light(0.6, 50.0);
    let (w, h) = (32, 32);
    for bounces in [Bounces::Limited(0), Bounces::Limited(1)] {
        let image = trace(&gpu, &scene, &settings(w, h, 1024, bounces, 3)).combined();
        let mut worst = 0.0f32;
        for y in 0..h {
            for x in 0..w {
                let expected = analytic_plane_radiance(&scene, x, y, w, h);
                let got = image.at(x, y)[0];
                worst = worst.max((got / expected - 1.0).abs());
            }
        }
        eprintln!("plane under a point light, {bounces:?}: worst relative error {worst:.2e}");
        assert!(worst < 0.01, "{bounces:?}: worst relative error {worst}");
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_lambertian_plane_under_a_square_area_light_matches_the_closed_form() {
    let gpu = common::gpu();
    let (albedo, side, height, le) = (0.6f32, 0.8f32, 1.0f32, 5.0f32);
    let scene = common::plane_under_square_light(albedo, side, height, le);
    let (w, h) = (32, 24);
    let image = trace(&gpu, &scene, &settings(w, h, 4096, Bounces::Limited(0), 5)).direct;
    let (mut worst, mut bias, mut checked) = (0.0f64, 0.0f64, 0);
    for y in 0..h {
        for x in 0..w {
            // The closed form averaged over the pixel's footprint (8x8 points), for pixels that
            // see the floor across all of it (not the emitter, not beyond the floor's middle).
            let n = 8;
            let mut sum = 0.0;
            let mut covered = true;
            for j in 0..n {
                for i in 0..n {
                    let px = Vec2::new(
                        x as f32 + (i as f32 + 0.5) / n as f32,
                        y as f32 + (j as f32 + 0.5) / n as f32,
                    );
                    let dir = scene.camera.ray_direction(px, w, h);
                    let hit = scene.mesh.intersect(scene.camera.position, dir, 1e-4, 1e9);
                    let floor = hit.filter(|hit| scene.mesh.materials[hit.triangle] == 0);
                    let Some(hit) = floor else {
                        covered = false;
                        continue;
                    };
                    let p = scene.camera.position + dir * hit.t;
                    covered &= p.x.abs() <= 1.5 && p.z.abs() <= 1.5;
                    sum += common::square_light_irradiance(p, side, height, le);
                }
            }
            if !covered {
                continue;
            }
            let expected = f64::from(albedo) / std::f64::consts::PI * sum / f64::from(n * n);
            let got = f64::from(image.at(x, y)[0]);
            worst = worst.max((got / expected - 1.0).abs());
            bias += got / expected - 1.0;
            checked += 1;
        }
    }
    let bias = bias / f64::from(checked);
    eprintln!(
        "plane under a square light: {checked} pixels, mean relative error {bias:.2e}, worst {worst:.2e}"
    );
    assert!(checked > 100, "enough floor pixels: {checked}");
    // Unbiased (the mean over 160 pixels) and within noise per pixel (about 0.7% at 4096 spp).
    assert!(bias.abs() < 0.003, "mean relative error {bias}");
    assert!(worst < 0.035, "worst relative error {worst}");
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn multiple_importance_sampling_beats_either_strategy_alone() {
    // A small bright emitter (light sampling is good at it) and a large dim one close to the
    // floor (BSDF sampling is good at it): their combination beats both on the same samples.
    let gpu = common::gpu();
    let mut scene = common::plane_under_square_light(0.8, 0.1, 1.0, 200.0);
    let wall =
        [(-2.0, 0.0), (2.0, 0.0), (2.0, 1.2), (-2.0, 1.2)].map(|(x, y)| Vec3::new(x, y, -0.4));
    for tri in [[0, 1, 2], [0, 2, 3]] {
        scene
            .mesh
            .push_triangle(tri.map(|i| wall[i]), [Vec3::ZERO; 3], 2);
    }
    scene.materials.push(vkgi::scene::Material {
        emission: Vec3::splat(0.5),
        ..vkgi::scene::Material::diffuse("dim wall", Vec3::ZERO)
    });
    let scene = Scene::new(
        scene.name.clone(),
        scene.mesh,
        scene.materials,
        vec![],
        scene.camera,
    )
    .unwrap();
    let (w, h) = (32, 24);
    let mut tracer = PathTracer::new(&gpu, &scene, w, h).unwrap();
    let mut with = |strategy, spp, seed| {
        let s = ReferenceSettings {
            strategy,
            ..settings(w, h, spp, Bounces::Limited(0), seed)
        };
        tracer.render(&gpu, &s, |_, _| {}).unwrap().direct
    };
    let truth = with(Strategy::Mis, 8192, 11);
    // Lit surfaces only: pixels that see the bright emitter itself are as noisy (pixel jitter
    // across its edge) for every strategy.
    let lit = |image: &HdrImage| {
        let keep = |t: &[f32; 3]| t[0] < 5.0;
        let pixels: Vec<[f32; 3]> = image
            .pixels
            .iter()
            .zip(&truth.pixels)
            .map(|(p, t)| if keep(t) { *p } else { [0.0; 3] })
            .collect();
        HdrImage::new(image.width, image.height, pixels)
    };
    let truth_lit = lit(&truth);
    let errors: Vec<(Strategy, f64)> = [Strategy::Mis, Strategy::Light, Strategy::Bsdf]
        .into_iter()
        .map(|strategy| (strategy, rmse(&lit(&with(strategy, 16, 3)), &truth_lit)))
        .collect();
    eprintln!("RMSE at 16 spp against 8192 spp: {errors:?}");
    let (mis, light, bsdf) = (errors[0].1, errors[1].1, errors[2].1);
    assert!(mis < light && mis < bsdf, "{errors:?}");
    // All three estimate the same image: with 128 times the samples their error falls about
    // 11 times (unbiased), not to a floor of their own.
    for (strategy, at_16) in [(Strategy::Light, light), (Strategy::Bsdf, bsdf)] {
        let converged = rmse(&lit(&with(strategy, 2048, 5)), &truth_lit);
        assert!(
            converged < 0.25 * at_16,
            "{strategy:?}: {converged} at 2048 spp, {at_16} at 16 spp"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn error_falls_as_one_over_the_square_root_of_the_sample_count() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (w, h) = (16, 12);
    let mut tracer = PathTracer::new(&gpu, &scene, w, h).unwrap();
    let truth = tracer
        .render(
            &gpu,
            &settings(w, h, 16384, Bounces::Limited(1), 99),
            |_, _| {},
        )
        .unwrap()
        .combined();
    let mut points = Vec::new();
    for k in 4..=10 {
        let spp = 1u32 << k;
        let image = tracer
            .render(
                &gpu,
                &settings(w, h, spp, Bounces::Limited(1), 1),
                |_, _| {},
            )
            .unwrap()
            .combined();
        points.push(((spp as f64).ln(), rmse(&image, &truth).ln()));
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let slope = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / points.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    eprintln!("log-log slope of RMSE against spp over 16..1024: {slope:.3}");
    assert!((-0.6..=-0.4).contains(&slope), "slope {slope}");
    common::assert_no_validation_errors(&gpu);
}

/// Direct light of the path tracer (bounces 0) against the raster frame, away from geometric
/// edges, shadow-map edges and steep spot falloff, where the raster samples one point per pixel
/// with a filtered shadow map and the path tracer averages the pixel. Elsewhere both compute the
/// same integral: the raster is within 0.3% of the analytic value (tests/raster.rs), the path
/// tracer's 64 jittered samples average radiance that varies by under 1% across such a pixel,
/// and the G-buffer keeps albedo in half floats (0.05%): so 2% per pixel.
#[test]
fn direct_only_reference_agrees_with_the_raster_frame() {
    let gpu = common::gpu();
    for name in ["cornell", "cornell-glossy"] {
        direct_light_agrees(&gpu, &Scene::load(name).unwrap());
    }
    common::assert_no_validation_errors(&gpu);
}

/// The raster frame's direct light against the path tracer's (Lambertian and glossy lobes),
/// away from shadow and material edges.
fn direct_light_agrees(gpu: &vkgi::gpu::Gpu, scene: &Scene) {
    let (w, h) = (120, 90);
    let (_, raster) = common::render(gpu, scene, w, h);
    let reference = trace(gpu, scene, &settings(w, h, 64, Bounces::Limited(0), 5)).combined();
    let light = scene.lights[0];
    // Direct radiance seen through a point of the image, on the CPU (None: background).
    let direct_at = |px: Vec2| -> Option<(usize, f32)> {
        let dir = scene.camera.ray_direction(px, w, h);
        let hit = scene
            .mesh
            .intersect(scene.camera.position, dir, 1e-4, 1e9)?;
        let p = scene.camera.position + dir * hit.t;
        let mut n = scene.mesh.face_normal(hit.triangle);
        if n.dot(dir) > 0.0 {
            n = -n;
        }
        let lit = scene.mesh.visible(p + n * 1e-4, light.position, 1e-4);
        let m = &scene.materials[scene.mesh.materials[hit.triangle] as usize];
        if !lit {
            return Some((hit.triangle, 0.0));
        }
        let e = light.irradiance_at(p, n);
        let to_light = (light.position - p).normalize();
        let glossy = vkgi::scene::brdf::glossy_cos(m.specular, m.roughness, n, to_light, -dir) * e
            / n.dot(to_light).max(1e-6);
        Some((
            hit.triangle,
            (m.albedo * e / std::f32::consts::PI + glossy).length(),
        ))
    };
    let (mut compared, mut masked) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            // The pixel and its 8 neighbours: one pixel spans the PCF kernel's reach here.
            let offsets = [
                (0.0, 0.0),
                (-1.0, -1.0),
                (0.0, -1.0),
                (1.0, -1.0),
                (-1.0, 0.0),
                (1.0, 0.0),
                (-1.0, 1.0),
                (0.0, 1.0),
                (1.0, 1.0),
            ];
            let samples: Vec<_> = offsets
                .iter()
                .map(|&(dx, dy)| direct_at(centre + Vec2::new(dx, dy)))
                .collect();
            let Some((tri, value)) = samples[0] else {
                continue;
            };
            let uniform = samples.iter().all(|s| {
                s.is_some_and(|(t, v)| {
                    scene
                        .mesh
                        .face_normal(t)
                        .dot(scene.mesh.face_normal(tri))
                        .abs()
                        > 0.999
                        && (v - value).abs() <= 0.05 * value.max(1e-3)
                })
            });
            if !uniform {
                masked += 1;
                continue;
            }
            let (r, p) = (raster[(y * w + x) as usize], reference.at(x, y));
            for c in 0..3 {
                let scale = p[c].max(0.02 * value.max(1e-3));
                assert!(
                    (r[c] - p[c]).abs() <= 0.02 * scale,
                    "pixel ({x},{y}) channel {c}: raster {} vs reference {}",
                    r[c],
                    p[c]
                );
            }
            compared += 1;
        }
    }
    eprintln!(
        "{}: {compared} pixels compared, {masked} masked as edges",
        scene.name
    );
    assert!(
        compared > (w * h / 3) as usize,
        "only {compared} pixels compared"
    );
}

#[test]
fn gpu_and_cpu_estimators_agree() {
    let gpu = common::gpu();
    let cornell = Scene::load("cornell").unwrap();
    // Emitters sampled by power and hit by bounces, combined by MIS: the same on both sides.
    let emitting = common::plane_under_square_light(0.6, 0.8, 1.0, 5.0);
    let textured = common::textured_plane_under_point_light(10.0);
    let glossy = Scene::load("cornell-glossy").unwrap();
    let mut glossy_emitting = emitting.clone();
    glossy_emitting.materials[0] = glossy_emitting.materials[0]
        .clone()
        .with_gloss(Vec3::splat(0.3), 0.3);
    let cases = [
        (&glossy, Bounces::Unlimited),
        (&glossy_emitting, Bounces::Limited(1)),
        (&textured, Bounces::Limited(0)),
        (&cornell, Bounces::Limited(1)),
        (&cornell, Bounces::Unlimited),
        (&emitting, Bounces::Limited(1)),
        (&emitting, Bounces::Unlimited),
    ];
    for (scene, bounces) in cases {
        let s = settings(32, 32, 8, bounces, 11);
        let on_gpu = trace(&gpu, scene, &s);
        let on_cpu = vkgi::reference::cpu::render(scene, &s, 2, |_, _| {}).unwrap();
        for (part, g, c) in [
            ("direct", &on_gpu.direct, &on_cpu.direct),
            ("indirect", &on_gpu.indirect, &on_cpu.indirect),
        ] {
            let mut close = 0;
            for (a, b) in g.pixels.iter().zip(&c.pixels) {
                let ok = (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-3 * b[k].abs().max(1e-2));
                close += usize::from(ok);
            }
            let fraction = close as f64 / g.pixels.len() as f64;
            assert!(
                fraction >= 0.99,
                "{} {bounces:?} {part}: only {:.1}% of pixels agree",
                scene.name,
                100.0 * fraction
            );
            let mean = |i: &HdrImage| {
                i.pixels
                    .iter()
                    .flatten()
                    .map(|&v| f64::from(v))
                    .sum::<f64>()
            };
            let (mg, mc) = (mean(g), mean(c));
            assert!(
                (mg - mc).abs() <= 1e-3 * mc.abs().max(1e-6),
                "{} {bounces:?} {part}: {mg} vs {mc}",
                scene.name
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_cpu_estimator_gives_the_same_bits_on_any_number_of_threads() {
    // Rows go to whichever thread asks next, but each pixel's samples are summed by one thread
    // in one order: the thread count must not show in the image (40 spp: three batches).
    let scene = Scene::load("cornell-area").unwrap();
    let s = settings(24, 20, 40, Bounces::Unlimited, 3);
    let one = vkgi::reference::cpu::render(&scene, &s, 1, |_, _| {}).unwrap();
    let mut batches = Vec::new();
    let three =
        vkgi::reference::cpu::render(&scene, &s, 3, |done, total| batches.push((done, total)))
            .unwrap();
    assert_eq!(batches, [(16, 40), (32, 40), (40, 40)]);
    for (a, b) in [
        (&one.direct, &three.direct),
        (&one.indirect, &three.indirect),
    ] {
        assert_eq!(a.pixels, b.pixels);
    }
    assert!(one.indirect.pixels.iter().flatten().any(|&v| v > 0.0));
}

#[test]
fn renders_are_deterministic_per_seed_and_split_into_direct_and_indirect() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let a = trace(&gpu, &scene, &settings(24, 18, 4, Bounces::Limited(1), 1));
    let b = trace(&gpu, &scene, &settings(24, 18, 4, Bounces::Limited(1), 1));
    let c = trace(&gpu, &scene, &settings(24, 18, 4, Bounces::Limited(1), 2));
    assert_eq!(a.combined(), b.combined());
    assert_ne!(a.combined(), c.combined());
    let direct_only = trace(&gpu, &scene, &settings(24, 18, 4, Bounces::Limited(0), 1));
    assert!(
        direct_only
            .indirect
            .pixels
            .iter()
            .flatten()
            .all(|&v| v == 0.0)
    );
    assert!(a.indirect.pixels.iter().flatten().any(|&v| v > 0.0));
    // Direct light does not depend on the bounce limit.
    assert_eq!(direct_only.direct, a.direct);
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_cache_reuses_only_an_identical_reference() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let s = settings(12, 9, 2, Bounces::Limited(1), 1);
    let images = trace(&gpu, &scene, &s);
    let dir = std::env::temp_dir().join(format!("vkgi-cache-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ref.exr");
    let key = cache::key(&scene, &s);
    let record = CacheRecord {
        key: key.clone(),
        split: true,
        seconds: 0.1,
        device: gpu.info.name.clone(),
    };
    cache::store(&path, &images, &record).unwrap();
    let cached = cache::load(&path, &key).expect("same scene, settings and code");
    assert_eq!(cached.combined(), images.combined());
    let other_spp = cache::key(&scene, &settings(12, 9, 4, Bounces::Limited(1), 1));
    assert!(cache::load(&path, &other_spp).is_none());
    let other_scene = cache::key(&Scene::load("two-rooms").unwrap(), &s);
    assert!(cache::load(&path, &other_scene).is_none());
    let mut other_code = key.clone();
    other_code.code_version.push('x');
    assert!(cache::load(&path, &other_code).is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}
