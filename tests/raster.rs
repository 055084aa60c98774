//! The raster frame on lavapipe, validation on: colours where the Cornell box has them, shadows
//! where the blocks cast them, and direct irradiance equal to the analytic value.

mod common;

use glam::{Vec2, Vec3};
use vkgi::scene::Scene;

const W: u32 = 160;
const H: u32 = 120;

/// Pixels of an HDR image with a luminance above 1e-3.
fn lit_pixels(image: &[[f32; 3]]) -> usize {
    image
        .iter()
        .filter(|p| common::luminance(**p) > 1e-3)
        .count()
}

/// The pixel a world point lands on (must be in the image).
fn pixel_of(scene: &Scene, p: Vec3) -> (u32, u32) {
    let px = scene
        .camera
        .project(p, W, H)
        .expect("point in front of the camera");
    assert!(
        px.x >= 0.0 && px.y >= 0.0 && px.x < W as f32 && px.y < H as f32,
        "{p} off-screen"
    );
    (px.x as u32, px.y as u32)
}

/// The surface point seen through the centre of pixel (x, y), if any.
fn surface_at(scene: &Scene, x: u32, y: u32) -> Option<(Vec3, usize)> {
    let dir = scene
        .camera
        .ray_direction(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), W, H);
    let hit = scene
        .mesh
        .intersect(scene.camera.position, dir, 1e-4, 1e9)?;
    Some((scene.camera.position + dir * hit.t, hit.triangle))
}

fn material_name(scene: &Scene, triangle: usize) -> &str {
    &scene.materials[scene.mesh.materials[triangle] as usize].name
}

#[test]
fn cornell_walls_have_their_colours_and_the_floor_is_lit() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (_, hdr) = common::render(&gpu, &scene, W, H);
    common::assert_no_validation_errors(&gpu);
    let light = scene.lights[0];
    // Every directly lit pixel of a coloured wall shows that colour; the red wall is on the
    // camera's left, the green one on its right.
    let (mut red, mut green) = (Vec::new(), Vec::new());
    for y in 0..H {
        for x in 0..W {
            let Some((p, tri)) = surface_at(&scene, x, y) else {
                continue;
            };
            let lit = scene.mesh.visible(p, light.position, 1e-3)
                && light.profile((p - light.position).normalize()) > 0.5;
            if !lit {
                continue;
            }
            let c = hdr[(y * W + x) as usize];
            match material_name(&scene, tri) {
                "red" => red.push((x, c)),
                "green" => green.push((x, c)),
                _ => {}
            }
        }
    }
    assert!(
        red.len() > 20 && green.len() > 20,
        "{} red and {} green lit pixels",
        red.len(),
        green.len()
    );
    for &(x, c) in &red {
        assert!(
            x < W / 2 && c[0] > 3.0 * c[1] && c[0] > 3.0 * c[2],
            "red wall pixel at x={x}: {c:?}"
        );
    }
    for &(x, c) in &green {
        assert!(
            x > W / 2 && c[1] > 2.0 * c[0] && c[1] > 2.0 * c[2],
            "green wall pixel at x={x}: {c:?}"
        );
    }
    // The floor right below the light (beside the short block) is lit as the spot predicts.
    let below = Vec3::new(light.position.x + 0.02, 0.0, light.position.z);
    let (x, y) = pixel_of(&scene, below);
    let expected = light.irradiance_at(below, Vec3::Y).x * 0.725 / std::f32::consts::PI;
    let seen = hdr[(y * W + x) as usize][0];
    assert!(
        (seen / expected - 1.0).abs() < 0.05,
        "floor under the light {seen}, expected ~{expected}"
    );
}

#[test]
fn the_blocks_cast_shadows_on_the_floor() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (_, hdr) = common::render(&gpu, &scene, W, H);
    common::assert_no_validation_errors(&gpu);
    let light = scene.lights[0].position;
    let mut shadowed = Vec::new();
    let mut open = Vec::new();
    // Classify every visible floor pixel by CPU ray casting; keep those whose whole 2 cm
    // neighbourhood agrees (away from soft shadow-map edges).
    for y in 0..H {
        for x in 0..W {
            let Some((p, tri)) = surface_at(&scene, x, y) else {
                continue;
            };
            if material_name(&scene, tri) != "white"
                || scene.mesh.face_normal(tri).y.abs() < 0.99
                || p.y > 1e-3
            {
                continue;
            }
            let lit = |q: Vec3| scene.mesh.visible(q + Vec3::Y * 1e-4, light, 1e-4);
            let around = [
                Vec3::ZERO,
                Vec3::X * 0.02,
                Vec3::X * -0.02,
                Vec3::Z * 0.02,
                Vec3::Z * -0.02,
            ];
            let states: Vec<bool> = around.iter().map(|&o| lit(p + o)).collect();
            let irradiance = scene.lights[0].irradiance_at(p, Vec3::Y).x;
            let lum = common::luminance(hdr[(y * W + x) as usize]);
            if states.iter().all(|&s| !s) && scene.lights[0].profile((p - light).normalize()) > 0.99
            {
                shadowed.push(lum);
            } else if states.iter().all(|&s| s) && irradiance > 0.0 {
                open.push(lum);
            }
        }
    }
    assert!(
        shadowed.len() >= 10,
        "too few shadowed floor pixels ({}) to test",
        shadowed.len()
    );
    assert!(open.len() >= 10);
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (dark, bright) = (mean(&shadowed), mean(&open));
    assert!(
        dark < 0.05 * bright,
        "shadowed floor {dark} vs open floor {bright}"
    );
}

/// Radiance of a Lambertian floor is albedo/π · E; E from the spot's profile, 1/r² and cosine.
#[test]
fn direct_irradiance_matches_the_analytic_spot_light_within_two_percent() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (_, hdr) = common::render(&gpu, &scene, W, H);
    common::assert_no_validation_errors(&gpu);
    let light = scene.lights[0];
    let white = scene
        .materials
        .iter()
        .find(|m| m.name == "white")
        .unwrap()
        .albedo;
    let mut checked = 0;
    let mut worst = 0.0f32;
    for y in (0..H).step_by(3) {
        for x in (0..W).step_by(3) {
            let Some((p, tri)) = surface_at(&scene, x, y) else {
                continue;
            };
            if material_name(&scene, tri) != "white" || p.y > 1e-3 {
                continue;
            }
            // Fully lit (away from shadow edges) and well inside the cone.
            let around = [
                Vec3::ZERO,
                Vec3::X * 0.03,
                Vec3::X * -0.03,
                Vec3::Z * 0.03,
                Vec3::Z * -0.03,
            ];
            if !around.iter().all(|&o| {
                scene
                    .mesh
                    .visible(p + o + Vec3::Y * 1e-4, light.position, 1e-4)
            }) {
                continue;
            }
            let expected = light.irradiance_at(p, Vec3::Y);
            if expected.x <= 0.0 {
                continue;
            }
            let pixel = hdr[(y * W + x) as usize];
            for c in 0..3 {
                let measured = std::f32::consts::PI * pixel[c] / white[c];
                let error = (measured / expected[c] - 1.0).abs();
                worst = worst.max(error);
                assert!(
                    error < 0.02,
                    "pixel ({x},{y}) channel {c}: E = {measured}, analytic {}",
                    expected[c]
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 50, "only {checked} floor pixels checked");
    eprintln!(
        "{checked} floor pixels, worst relative irradiance error {:.3}%",
        100.0 * worst
    );
}

/// Direct lighting reads up to `MAX_SHARED_LIGHTS` lights at constant indices and selects each
/// pixel's shadow view among a light's views; more lights take the loop that reads them per
/// pixel. Both must give the same image: a point light (6 views), a wide spot (5), a narrow spot
/// (1) and a cosine lobe (5), then the same with dark lights added to pass the limit.
#[test]
fn shared_and_looped_lights_give_the_same_direct_light() {
    use vkgi::scene::{Light, LightKind};
    let gpu = common::gpu();
    let mut scene = Scene::load("cornell").unwrap();
    let at = |x: f32, z: f32| Vec3::new(x, 0.45, z);
    let light = |position: Vec3, kind: LightKind, flux: f32| Light {
        position,
        kind,
        flux,
        color: Vec3::new(1.0, 0.9, 0.8),
    };
    let spot = |cone_angle_deg: f32| LightKind::Spot {
        direction: Vec3::new(0.2, -1.0, 0.1),
        cone_angle_deg,
        penumbra_deg: 10.0,
    };
    let cosine = LightKind::Cosine {
        direction: Vec3::NEG_Y,
    };
    scene.lights = vec![
        light(at(0.15, 0.2), LightKind::Point, 0.3),
        light(at(0.4, 0.3), spot(75.0), 0.3),
        light(at(0.3, 0.4), spot(25.0), 0.3),
        light(at(0.25, 0.25), cosine, 0.3),
    ];
    let (_, shared) = common::render(&gpu, &scene, 96, 72);
    let lights = scene.lights.len();
    scene.lights.extend(
        (0..=vkgi::render::passes::MAX_SHARED_LIGHTS - lights)
            .map(|i| light(at(0.1 + 0.05 * i as f32, 0.3), LightKind::Point, 0.0)),
    );
    let (_, looped) = common::render(&gpu, &scene, 96, 72);
    common::assert_no_validation_errors(&gpu);
    let lit = lit_pixels(&shared);
    assert!(lit > shared.len() / 2, "only {lit} lit pixels");
    assert_eq!(
        shared, looped,
        "the shared-light and looped-light paths differ"
    );
}

/// Direct lighting is a fragment pass when the shared lights and their shadow views fit its
/// flat varyings (one narrow spot: the Cornell box), a compute pass otherwise. Both must give the
/// same bits: the Cornell box with glossy and plain materials under its spot, against the same
/// scene with dark lights added past the shared limit (the compute pass's loop), which shades
/// the background pixels the fragment form skips.
#[test]
fn fragment_and_compute_direct_lighting_give_the_same_image() {
    use vkgi::scene::{Light, LightKind};
    let gpu = common::gpu_with(Some(vkgi::gpu::PixelPasses::Fragment));
    let mut scene = Scene::load("cornell").unwrap();
    for (i, material) in scene.materials.iter_mut().enumerate() {
        if i % 2 == 0 {
            material.albedo *= 0.5;
            material.specular = Vec3::splat(0.4);
            material.roughness = 0.3;
        }
    }
    let (fragment_frame, fragment) = common::render(&gpu, &scene, 96, 72);
    assert!(
        fragment_frame
            .direct_lighting()
            .starts_with("fragment pass"),
        "the Cornell box's spot should be lit by the fragment pass: {}",
        fragment_frame.direct_lighting()
    );
    // The fragment form shades only the pixels a surface covers (the early depth test against
    // the G-buffer's depth skips the rest) and the compute form every pixel: the view must hold
    // background pixels for the comparison below to cover that.
    let positions = fragment_frame.read_positions(&gpu).unwrap();
    let background = positions.iter().filter(|p| p[3] == 0.0).count();
    assert!(
        background > positions.len() / 10 && background < positions.len() / 2,
        "{background} of {} pixels are background",
        positions.len()
    );
    let dark = Light {
        position: Vec3::new(0.2, 0.4, 0.3),
        kind: LightKind::Point,
        flux: 0.0,
        color: Vec3::ONE,
    };
    scene.lights.extend(std::iter::repeat_n(
        dark,
        vkgi::render::passes::MAX_SHARED_LIGHTS,
    ));
    let (compute_frame, compute) = common::render(&gpu, &scene, 96, 72);
    assert!(compute_frame.direct_lighting().starts_with("compute pass"));
    common::assert_no_validation_errors(&gpu);
    let lit = lit_pixels(&fragment);
    // The spot's cone lights the floor, the blocks and the walls' lower parts.
    assert!(lit > fragment.len() / 5, "only {lit} lit pixels");
    assert_eq!(fragment, compute, "the fragment and compute passes differ");
}

#[test]
fn two_rooms_scene_renders_its_lit_room() {
    let gpu = common::gpu();
    let scene = Scene::load("two-rooms").unwrap();
    let (_, hdr) = common::render(&gpu, &scene, 96, 64);
    common::assert_no_validation_errors(&gpu);
    let bright = hdr.iter().filter(|p| common::luminance(**p) > 0.05).count();
    assert!(
        bright > hdr.len() / 4,
        "room A should be mostly lit ({bright} of {} pixels)",
        hdr.len()
    );
}

#[test]
fn area_light_samples_converge_to_the_path_traced_direct_light() {
    // The Cornell box lit by its published ceiling light alone: the rasteriser sees the light
    // as N cosine-lobed lights on it; its direct light approaches the path tracer's direct part
    // (which samples the light exactly) as N grows.
    let gpu = common::gpu();
    let (w, h) = (64, 48);
    let mut scene = Scene::load("cornell-area").unwrap();
    let settings = vkgi::reference::ReferenceSettings {
        width: w,
        height: h,
        spp: 512,
        bounces: vkgi::reference::Bounces::Limited(0),
        seed: 2,
        strategy: Default::default(),
    };
    let mut tracer = vkgi::reference::PathTracer::new(&gpu, &scene, w, h).unwrap();
    let truth = tracer.render(&gpu, &settings, |_, _| {}).unwrap().direct;
    // Lit surfaces only: the light itself, seen directly, is the same in both.
    let lit: Vec<bool> = truth.pixels.iter().map(|p| p[0] < 5.0).collect();
    let mut errors = Vec::new();
    for samples in [1, 4, 16] {
        scene.area_samples = samples;
        let (_, pixels) = common::render(&gpu, &scene, w, h);
        let image = vkgi::imageio::HdrImage::new(w, h, pixels);
        let m = vkgi::metrics::compare(&image, &truth, Some(&lit)).unwrap();
        errors.push((samples, m.rmse, m.rel_mse));
    }
    eprintln!("area samples against the path-traced direct light: {errors:?}");
    assert!(
        errors
            .windows(2)
            .all(|e| e[1].1 < e[0].1 && e[1].2 < e[0].2),
        "error falls with the sample count: {errors:?}"
    );
    common::assert_no_validation_errors(&gpu);
}

/// The 8-bit image tone mapping writes, in both its forms (a fragment pass rendering through the
/// sRGB view of its target, whose attachment encodes sRGB; a compute pass encoding it and
/// storing to the UNORM view, a GPU's form), is the CPU's tone map of the HDR image
/// (`metrics::tonemap_srgb8`, Reinhard and the IEC 61966-2-1 curve) within one in every byte,
/// over every value the image spans: a Cornell box with its light from dim to so bright that
/// the walls near it saturate.
#[test]
fn the_tone_mapped_image_is_the_cpu_tone_map_of_the_hdr_image_within_one() {
    use vkgi::gpu::PixelPasses;
    for form in [PixelPasses::Fragment, PixelPasses::Compute] {
        let gpu = common::gpu_with(Some(form));
        assert_tone_map_within_one(&gpu, form);
        common::assert_no_validation_errors(&gpu);
    }
}

/// Fail unless `gpu`'s tone map, in `form`, of dim to saturated Cornell boxes is the CPU's within
/// one.
fn assert_tone_map_within_one(gpu: &vkgi::gpu::Gpu, form: vkgi::gpu::PixelPasses) {
    use vkgi::imageio::HdrImage;
    let (width, height) = (64u32, 48u32);
    let pass = match form {
        vkgi::gpu::PixelPasses::Fragment => "fragment pass",
        vkgi::gpu::PixelPasses::Compute => "compute pass",
    };
    for flux in [0.05f32, 1.0, 20.0] {
        let mut scene = Scene::load("cornell").unwrap();
        scene.lights[0].flux *= flux;
        let (frame, hdr) = common::render(gpu, &scene, width, height);
        assert!(
            frame.tone_map().starts_with(pass),
            "{form:?}: {}",
            frame.tone_map()
        );
        let expected = vkgi::metrics::tonemap_srgb8(&HdrImage::new(width, height, hdr));
        let ldr = frame.read_ldr(gpu).unwrap();
        let rgb: Vec<u8> = ldr.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(rgb.len(), expected.len());
        let worst = rgb.iter().zip(&expected).map(|(a, b)| a.abs_diff(*b)).max();
        assert!(
            worst <= Some(1),
            "{form:?}, flux x{flux}: bytes differ by {worst:?}"
        );
        let distinct: std::collections::BTreeSet<u8> = rgb.iter().copied().collect();
        assert!(
            distinct.len() > 20,
            "{form:?}, flux x{flux}: only {} values",
            distinct.len()
        );
    }
}

/// A pass that shades only covered pixels tests against the G-buffer's depth: recorded without
/// a depth attachment it is refused with the pass named, before anything is recorded, and so
/// is a depth attachment for a pipeline that has no depth format.
#[test]
fn a_pass_and_its_pipeline_must_agree_on_a_depth_attachment() {
    use ash::vk;
    use vkgi::gpu::{Draw, ImageDesc, RasterPass, Specialization};
    use vkgi::render::full_screen::{Blend, Pixels, full_screen};
    let gpu = common::gpu();
    let target = vk::Format::R32G32B32A32_SFLOAT;
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
    let hdr = gpu
        .create_image(&ImageDesc::new_2d("hdr", target, 8, 8, usage))
        .unwrap();
    let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
    let depth_format = vk::Format::D32_SFLOAT;
    let depth = gpu
        .create_image(&ImageDesc::new_2d("depth", depth_format, 8, 8, depth_usage))
        .unwrap();
    let spec = Specialization::new();
    let shader = vkgi::shaders::RASTER_TONEMAP_FRAG;
    let pipeline = |name, pixels| {
        full_screen(&gpu, name, shader, (target, pixels), Blend::Add, &spec).unwrap()
    };
    let (covered, every) = (
        pipeline("covered", Pixels::Covered),
        pipeline("every", Pixels::All),
    );
    for (name, pipeline, with_depth, expected) in [
        ("covered", &covered, false, "no depth attachment"),
        ("every", &every, true, "no format for"),
    ] {
        let result = gpu.one_shot(|rec| {
            rec.raster(&RasterPass {
                name: "agreement",
                pipeline,
                bindings: &[],
                push: &(),
                color: &[(&hdr, 0, [0.0; 4])],
                depth: with_depth.then_some((&depth, 0)),
                draw: Draw::Vertices(3),
                keep_contents: true,
            })
        });
        let message = format!("{:#}", result.expect_err(name));
        assert!(
            message.contains("agreement") && message.contains(expected),
            "{name}: {message}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// The ambient baseline drawn inside direct lighting (one fragment pass, the G-buffer read
/// once) gives the image of direct lighting followed by its compute pass apart, with direct
/// light and with indirect light alone; and that indirect light is albedo · E / π in f64 of the
/// surface each pixel sees (found by a ray through its centre), E given, within the G-buffer's
/// half-float albedo, at all but the pixels along edges, where the ray and the rasteriser may
/// see different surfaces.
#[test]
fn the_ambient_term_inside_direct_lighting_is_albedo_times_e_over_pi() {
    const LIT: &str = "direct lighting + ambient";
    let gpu = common::gpu_with(Some(vkgi::gpu::PixelPasses::Fragment));
    let scene = Scene::load("cornell").unwrap();
    let entry = vkgi::gi::registry::find("ambient").unwrap();
    let e = [0.5, 0.25, 2.0];
    let irradiance = ("ambient-irradiance".to_string(), "0.5,0.25,2".to_string());
    let settings = entry.settings(&[irradiance]).unwrap();
    let run = |indirect_only: bool, lookup_apart: bool| {
        let options = vkgi::render::FrameOptions {
            width: W,
            height: H,
            indirect_only,
            lookup_apart,
            ..vkgi::render::FrameOptions::default()
        };
        let mut frame = vkgi::render::Frame::new(&gpu, &scene, options).unwrap();
        let mut method = entry
            .create(&vkgi::gi::registry::Setup::new(&gpu, &scene), &settings)
            .unwrap();
        let passes = common::run_naming_passes(&gpu, &mut frame, method.as_mut(), 2);
        (frame.read_hdr(&gpu).unwrap(), passes)
    };
    for indirect_only in [false, true] {
        let (inside, inside_passes) = run(indirect_only, false);
        let (apart, apart_passes) = run(indirect_only, true);
        assert!(inside_passes.iter().any(|p| p == LIT), "{inside_passes:?}");
        assert!(
            !inside_passes.iter().any(|p| p == "ambient"),
            "{inside_passes:?}"
        );
        assert!(
            apart_passes.iter().any(|p| p == "ambient"),
            "{apart_passes:?}"
        );
        assert!(!apart_passes.iter().any(|p| p == LIT), "{apart_passes:?}");
        let (worst, brightest) = common::worst_difference(&inside, &apart);
        assert!(
            worst <= 1e-6 * brightest,
            "indirect only {indirect_only}: inside and apart differ by {worst} (brightest {brightest})"
        );
        if !indirect_only {
            continue;
        }
        let bvh = vkgi::scene::bvh::Bvh::build(&scene.mesh);
        let albedo = vkgi::gi::ambient::fit::albedo_image(&scene, &bvh, W, H);
        let mut matching = 0;
        let mut covered = 0;
        for (got, a) in inside.iter().zip(&albedo) {
            if a.iter().all(|&v| v == 0.0) {
                continue;
            }
            covered += 1;
            let close = (0..3).all(|c| {
                let want = f64::from(a[c]) * e[c] / std::f64::consts::PI;
                (f64::from(got[c]) - want).abs() <= 1e-3 * want.max(1e-6)
            });
            matching += usize::from(close);
        }
        assert!(covered > (W * H / 2) as usize, "{covered} covered pixels");
        assert!(
            matching as f64 >= 0.98 * covered as f64,
            "only {matching} of {covered} covered pixels are albedo · E / π"
        );
    }
    common::assert_no_validation_errors(&gpu);
}
