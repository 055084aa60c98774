//! LightWave (seed 002) on lavapipe with validation on: the GPU's rig against the f64 rig, the
//! GPU's gather against the f64 gather, and the indirect-shadow modes against each other.

mod common;

use glam::{DVec3, Vec3};
use vkgi::gi::GiMethod;
use vkgi::gi::lightwave::cpu::{gather, rig_axis};
use vkgi::gi::lightwave::rig::Vpl;
use vkgi::gi::lightwave::{LightWave, LightWaveSettings, ShadowMode};
use vkgi::gi::registry::{self, Setup};
use vkgi::render::runner::run_frames;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::{Mesh, Scene};

/// Settings from the command line's words.
fn settings(scene: &Scene, overrides: &[(&str, &str)]) -> LightWaveSettings {
    let entry = registry::find("lightwave").expect("registered");
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    let parsed = entry.settings(&overrides).expect("settings");
    LightWaveSettings::parse(&parsed, scene).expect("lightwave settings")
}

fn indirect(width: u32, height: u32) -> FrameOptions {
    FrameOptions {
        shadow_map_size: 256,
        ..common::indirect_only(width, height)
    }
}

#[test]
fn the_gpu_rig_is_the_f64_rig_and_follows_its_light() {
    let gpu = common::gpu();
    let mut scene = common::plane_under_point_light(0.5, 10.0);
    let s = settings(
        &scene,
        &[("lightwave-gain", "1"), ("lightwave-angle", "10")],
    );
    let rig = s.rig;
    let mut method = LightWave::with(&Setup::new(&gpu, &scene), s).expect("lightwave");
    let mut frame = Frame::new(&gpu, &scene, indirect(16, 12)).expect("frame");
    for moved in [false, true] {
        if moved {
            scene.lights[0].position += Vec3::new(0.5, -0.25, 1.0);
            frame.set_lights(&scene);
        }
        drop(run_frames(&gpu, &mut frame, Some(&mut method), 0, 1).expect("frame"));
        let gpu_vpls = method.read_vpls(&gpu).expect("readback");
        let light = &scene.lights[0];
        let cpu_vpls = rig.vpls(light.position.as_dvec3(), rig_axis(light));
        assert_eq!(cpu_vpls.len(), 1625);
        for (j, (g, c)) in gpu_vpls.iter().zip(&cpu_vpls).enumerate() {
            let position = DVec3::new(g[0].into(), g[1].into(), g[2].into());
            let direction = DVec3::new(g[4].into(), g[5].into(), g[6].into());
            assert!(
                (position - c.position).length() < 1e-5,
                "VPL {j}: {position} {}",
                c.position
            );
            assert!((direction - c.direction).length() < 1e-6, "VPL {j}");
            assert!((f64::from(g[3]) - c.weight).abs() < 1e-6, "VPL {j}");
            assert_eq!(g[7], 0.0, "light index");
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_gpu_gather_equals_the_f64_gather_and_no_maps_means_no_shadow() {
    let gpu = common::gpu();
    // A point light of intensity 1 W/sr over a plane of albedo 0.5, gain 1: radiance is
    // 0.5/π times the gather.
    let scene = common::plane_under_point_light(0.5, 4.0 * std::f32::consts::PI);
    let s = settings(
        &scene,
        &[
            ("lightwave-gain", "1"),
            ("lightwave-shadow-maps", "0"),
            ("lightwave-gather", "pixel"),
        ],
    );
    assert_eq!(s.shadows, ShadowMode::None);
    assert!(!s.per_vertex);
    let rig = s.rig;
    let mut method = LightWave::with(&Setup::new(&gpu, &scene), s).expect("lightwave");
    let (width, height) = (24, 18);
    let mut frame = Frame::new(&gpu, &scene, indirect(width, height)).expect("frame");
    drop(run_frames(&gpu, &mut frame, Some(&mut method), 0, 1).expect("frame"));
    let image = frame.read_hdr(&gpu).expect("readback");
    let positions = frame.read_positions(&gpu).expect("positions");
    let light = &scene.lights[0];
    let vpls = rig.vpls(light.position.as_dvec3(), rig_axis(light));
    let (mut compared, mut lit) = (0, 0);
    for (pixel, p) in image.iter().zip(&positions) {
        if p[3] == 0.0 {
            continue;
        }
        let point = DVec3::new(p[0].into(), p[1].into(), p[2].into());
        let want = 0.5 / std::f64::consts::PI * gather(&vpls, point, DVec3::Y);
        lit += u32::from(want > 1e-3);
        let got = f64::from(pixel[0]);
        assert!((got - want).abs() <= 1e-4 * want, "{got} vs {want}");
        compared += 1;
    }
    assert!(compared > width * height / 2, "{compared} pixels");
    assert!(
        lit > compared / 2,
        "the rig lights the plane: {lit} of {compared} pixels"
    );
    common::assert_no_validation_errors(&gpu);
}

/// The weights of `p` in triangle (a, b, c), or None when it lies outside (beyond `slack`).
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3], slack: f64) -> Option<[f64; 3]> {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let normal = e1.cross(e2);
    let area = normal.length_squared();
    let v = d.cross(e2).dot(normal) / area;
    let w = e1.cross(d).dot(normal) / area;
    let weights = [1.0 - v - w, v, w];
    weights.iter().all(|&x| x >= -slack).then_some(weights)
}

/// One frame of LightWave gathering per vertex with `settings` on `scene`'s first light: the
/// frame, the per-vertex values (front, back) and the f64 rig's VPLs.
fn vertex_gather_frame(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    settings: LightWaveSettings,
    (width, height): (u32, u32),
) -> (Frame, Vec<[f32; 2]>, Vec<Vpl>) {
    let rig = settings.rig;
    let mut method = LightWave::with(&Setup::new(gpu, scene), settings).expect("lightwave");
    let mut frame = Frame::new(gpu, scene, indirect(width, height)).expect("frame");
    drop(run_frames(gpu, &mut frame, Some(&mut method), 0, 1).expect("frame"));
    let light = &scene.lights[0];
    let vpls = rig.vpls(light.position.as_dvec3(), rig_axis(light));
    let values = method
        .read_vertex_values(gpu)
        .expect("readback")
        .expect("per vertex");
    (frame, values, vpls)
}

/// Assert that the per-vertex values (front, back) equal the f64 gather at every vertex of a
/// mesh lying in the y = 0 plane, front +Y and back -Y, within 1e-4 relative; whether some
/// vertex's back is lit.
fn assert_vertex_values_are_the_f64_gather(values: &[[f32; 2]], mesh: &Mesh, vpls: &[Vpl]) -> bool {
    let mut back_lit = false;
    for (v, got) in values.iter().enumerate() {
        let p = mesh.positions[v].as_dvec3();
        for (side, normal) in [(0, DVec3::Y), (1, DVec3::NEG_Y)] {
            let want = gather(vpls, p, normal);
            let got = f64::from(got[side]);
            assert!(
                (got - want).abs() <= 1e-4 * want + 1e-7,
                "vertex {v} side {side}: {got} vs {want}"
            );
            back_lit |= side == 1 && want > 1e-3;
        }
    }
    back_lit
}

#[test]
fn the_vertex_gather_is_the_f64_gather_at_every_vertex_interpolated_across_triangles() {
    let gpu = common::gpu();
    let scene = common::plane_under_point_light(0.5, 4.0 * std::f32::consts::PI);
    let s = settings(
        &scene,
        &[
            ("lightwave-gain", "1"),
            ("lightwave-shadow-maps", "0"),
            ("lightwave-gather", "vertex"),
        ],
    );
    assert!(s.per_vertex);
    let (width, height) = (24, 18);
    let (frame, values, vpls) = vertex_gather_frame(&gpu, &scene, s, (width, height));
    // Per vertex, both sides: the f64 gather.
    let mesh = &scene.mesh;
    assert_eq!(values.len(), mesh.positions.len());
    let back_lit = assert_vertex_values_are_the_f64_gather(&values, mesh, &vpls);
    assert!(back_lit, "some VPLs light the plane's underside too");
    // Per pixel: the front values, interpolated across the triangle the pixel lies in.
    let image = frame.read_hdr(&gpu).expect("readback");
    let positions = frame.read_positions(&gpu).expect("positions");
    let (mut compared, mut differs_from_pixel_gather) = (0, 0);
    for (pixel, p) in image.iter().zip(&positions) {
        if p[3] == 0.0 {
            continue;
        }
        let point = DVec3::new(p[0].into(), p[1].into(), p[2].into());
        let (corners, weights) = mesh
            .indices
            .iter()
            .find_map(|tri| {
                let corners = tri.map(|i| mesh.positions[i as usize].as_dvec3());
                barycentric(point, corners, 1e-5).map(|w| (corners, w))
            })
            .expect("the pixel lies in a triangle");
        let interpolated: f64 = (0..3)
            .map(|k| weights[k] * gather(&vpls, corners[k], DVec3::Y))
            .sum();
        let want = 0.5 / std::f64::consts::PI * interpolated;
        let got = f64::from(pixel[0]);
        assert!((got - want).abs() <= 1e-3 * want + 1e-6, "{got} vs {want}");
        let per_pixel = 0.5 / std::f64::consts::PI * gather(&vpls, point, DVec3::Y);
        differs_from_pixel_gather += u32::from((per_pixel - want).abs() > 1e-2 * want);
        compared += 1;
    }
    assert!(compared > width * height / 2, "{compared} pixels");
    assert!(
        differs_from_pixel_gather > 0,
        "two triangles cannot hold the rig's light exactly: the tessellation shows"
    );
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_vertex_gather_is_the_f64_gather_however_it_slices_the_vpls_and_without_normals() {
    let gpu = common::gpu();
    let plane = common::plane_under_point_light(0.5, 10.0);
    // Grids of quads of two triangles, three vertices each, with no vertex normals (so the
    // gather uses the faces', +Y here): 20 x 20 cells, 2400 vertices, split each vertex's VPLs
    // in 32 slices; 110 x 110, 72 600 vertices, in one (src/gi/lightwave/vertex.rs). The
    // one-triangle-pair plane of the test above takes a workgroup's 64.
    for cells in [20, 110] {
        let mut mesh = Mesh::default();
        for i in 0..cells {
            for j in 0..cells {
                let at = |di: u32, dj: u32| {
                    let t = |k: u32| -2.0 + 4.0 * k as f32 / cells as f32;
                    Vec3::new(t(i + di), 0.0, t(j + dj))
                };
                mesh.push_triangle([at(0, 0), at(0, 1), at(1, 1)], [Vec3::ZERO; 3], 0);
                mesh.push_triangle([at(0, 0), at(1, 1), at(1, 0)], [Vec3::ZERO; 3], 0);
            }
        }
        let scene = Scene::new(
            "grid".into(),
            mesh,
            plane.materials.clone(),
            plane.lights.clone(),
            plane.camera,
        )
        .expect("scene");
        let s = settings(
            &scene,
            &[
                ("lightwave-gain", "1"),
                ("lightwave-shadow-maps", "0"),
                ("lightwave-gather", "vertex"),
                ("lightwave-angle", "90"),
            ],
        );
        let (_, values, vpls) = vertex_gather_frame(&gpu, &scene, s, (16, 12));
        let vertices = (6 * cells * cells) as usize;
        assert_eq!(values.len(), vertices);
        assert!(
            values[vertices - 1][0] > 1e-3,
            "{cells} cells: the last row's vertices are lit: {:?}",
            values[vertices - 1]
        );
        assert_vertex_values_are_the_f64_gather(&values, &scene.mesh, &vpls);
    }
    common::assert_no_validation_errors(&gpu);
}

fn boxes_image(gpu: &vkgi::gpu::Gpu, scene: &Scene, s: LightWaveSettings) -> Vec<[f32; 3]> {
    let mut method = LightWave::with(&Setup::new(gpu, scene), s).expect("lightwave");
    assert!(method.describe().len() >= 3);
    common::render_with(gpu, scene, &mut method, indirect(40, 30), 1)
}

#[test]
fn integrated_shadows_at_one_step_are_the_mean_of_their_five_maps() {
    let gpu = common::gpu();
    let scene = Scene::load("lightwave-boxes").expect("scene");
    let base = [("lightwave-gain", "0.05"), ("lightwave-shadow-ratio", "1")];
    let one_step = settings(
        &scene,
        &[
            base[0],
            base[1],
            ("lightwave-shadows", "integrated"),
            ("lightwave-steps", "1"),
        ],
    );
    // Accurate mode over the same five VPLs: the plain mean of the same maps.
    let mut mean = settings(&scene, &[base[0], base[1], ("lightwave-shadow-maps", "5")]);
    mean.shadow_set = one_step.shadow_set.clone();
    assert_eq!(mean.shadows, ShadowMode::Accurate);
    let interpolated = settings(
        &scene,
        &[
            base[0],
            base[1],
            ("lightwave-shadows", "integrated"),
            ("lightwave-steps", "4"),
        ],
    );
    let unshadowed = settings(&scene, &[base[0], ("lightwave-shadow-maps", "0")]);
    let a = boxes_image(&gpu, &scene, one_step);
    let b = boxes_image(&gpu, &scene, mean);
    let (worst, peak) = common::worst_difference(&a, &b);
    assert!(worst <= 1e-5 * peak, "worst {worst} of peak {peak}");
    // The shadows are real: they darken the image, and interpolation changes it.
    let c = boxes_image(&gpu, &scene, interpolated);
    let d = boxes_image(&gpu, &scene, unshadowed);
    let (mean_a, mean_c, mean_d) = (common::mean(&a), common::mean(&c), common::mean(&d));
    assert!(
        mean_a < 0.995 * mean_d,
        "shadowed {mean_a} vs unshadowed {mean_d}"
    );
    assert!(
        common::worst_difference(&a, &c).0 > 1e-3 * peak,
        "{mean_a} {mean_c}"
    );
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_composites_add_what_the_thesis_adds_to_direct_light() {
    let gpu = common::gpu();
    let scene = Scene::load("lightwave-boxes").expect("scene");
    let options = || FrameOptions {
        width: 40,
        height: 30,
        shadow_map_size: 256,
        ..FrameOptions::default()
    };
    let render = |overrides: &[(&str, &str)]| {
        let s = settings(&scene, overrides);
        let mut method = LightWave::with(&Setup::new(&gpu, &scene), s).expect("lightwave");
        common::render_with(&gpu, &scene, &mut method, options(), 1)
    };
    let direct = {
        let mut frame = Frame::new(&gpu, &scene, options()).expect("frame");
        drop(run_frames(&gpu, &mut frame, None, 0, 1).expect("frame"));
        frame.read_hdr(&gpu).expect("readback")
    };
    // Composites without indirect light build none of it: no VPL maps, no vertex gather.
    for composite in ["direct-only", "fake"] {
        let s = settings(&scene, &[("lightwave-composite", composite)]);
        assert_eq!(
            (s.shadows, s.per_vertex, s.gain),
            (ShadowMode::None, false, Some(0.0))
        );
    }
    let direct_only = render(&[("lightwave-composite", "direct-only")]);
    let (worst, peak) = common::worst_difference(&direct_only, &direct);
    assert_eq!(worst, 0.0, "direct-only adds nothing (peak {peak})");
    // Fake indirect (eq 5.2) with m = 1: 0.5 shadowed + 0.5 unshadowed direct, which is at
    // least the shadowed direct light, and more where shadows fall.
    let fake = render(&[("lightwave-composite", "fake"), ("lightwave-fake", "1")]);
    let brighter = fake
        .iter()
        .zip(&direct)
        .filter(|(f, d)| f[0] > d[0] * 1.01 + 1e-6)
        .count();
    assert!(
        fake.iter()
            .zip(&direct)
            .all(|(f, d)| f[0] >= d[0] - 1e-5 * peak)
    );
    assert!(brighter > 0, "the shadows are half lifted somewhere");
    // eq 4.9 adds indirect light on top of the direct light.
    let eq49 = render(&[("lightwave-gain", "0.05")]);
    assert!(common::mean(&eq49) > common::mean(&direct) * 1.01);
    common::assert_no_validation_errors(&gpu);
}
