//! Helpers shared by the integration tests: a validated GPU and one-frame renders.
#![allow(dead_code)]

use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

/// A GPU context with the Khronos validation layers (synchronization validation included).
pub fn gpu() -> Gpu {
    Gpu::new(&GpuOptions {
        validation: true,
        device: None,
        display: None,
    })
    .expect("a Vulkan 1.3 device with validation layers (lavapipe in CI)")
}

/// Fail the test if the validation layers reported anything.
pub fn assert_no_validation_errors(gpu: &Gpu) {
    let errors = gpu.validation_errors();
    let first = gpu
        .validation_log()
        .map(|l| l.first_errors())
        .unwrap_or_default();
    assert_eq!(errors, 0, "validation errors: {first:#?}");
}

/// Render one raster frame of `scene` and return it with its linear HDR pixels.
pub fn render(gpu: &Gpu, scene: &Scene, width: u32, height: u32) -> (Frame, Vec<[f32; 3]>) {
    let mut frame = Frame::new(
        gpu,
        scene,
        FrameOptions {
            width,
            height,
            ..FrameOptions::default()
        },
    )
    .expect("frame");
    let mut ring = FrameRing::new(gpu, 2).expect("frame ring");
    ring.submit_frame(gpu, &gpu.queues.graphics, &[], |rec| {
        frame.record(rec, None)
    })
    .expect("frame");
    ring.finish().expect("finish");
    let hdr = frame.read_hdr(gpu).expect("readback");
    (frame, hdr)
}

pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

use glam::Vec3;
use vkgi::scene::{Camera, Light, LightKind, Material, Mesh};

/// A closed icosphere of radius `r` around the origin (flat faces, face normals).
pub fn icosphere(subdivisions: u32, r: f32) -> Mesh {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut next = Vec::new();
        let mut midpoint = std::collections::HashMap::new();
        let mut mid = |a: usize, b: usize, v: &mut Vec<Vec3>| -> usize {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a] + v[b]) * 0.5).normalize());
                v.len() - 1
            })
        };
        for [a, b, c] in faces {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let mut mesh = Mesh::default();
    for [a, b, c] in faces {
        let n = (v[b] - v[a]).cross(v[c] - v[a]).normalize();
        mesh.push_triangle([a, b, c].map(|i| v[i] * r), [n; 3], 0);
    }
    mesh
}

/// The white furnace: a camera at the centre of a closed emissive sphere of albedo `albedo`.
pub fn furnace(albedo: f32, emission: f32) -> Scene {
    let material = Material {
        name: "furnace".into(),
        albedo: Vec3::splat(albedo),
        emission: Vec3::splat(emission),
    };
    let camera = Camera {
        position: Vec3::ZERO,
        target: Vec3::Z,
        up: Vec3::Y,
        vfov_deg: 90.0,
    };
    Scene::new(
        "furnace".into(),
        icosphere(2, 1.0),
        vec![material],
        vec![],
        camera,
    )
    .unwrap()
}

/// A 4 m square Lambertian plane at y = 0 under a point light, seen from above.
pub fn plane_under_point_light(albedo: f32, flux: f32) -> Scene {
    let mut mesh = Mesh::default();
    let corners = [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)];
    for tri in [[0, 1, 2], [0, 2, 3]] {
        let corner = |i: usize| Vec3::new(corners[i].0, 0.0, corners[i].1);
        mesh.push_triangle(tri.map(corner), [Vec3::Y; 3], 0);
    }
    let material = Material {
        name: "plane".into(),
        albedo: Vec3::splat(albedo),
        emission: Vec3::ZERO,
    };
    let light = Light {
        position: Vec3::new(0.3, 1.0, -0.2),
        kind: LightKind::Point,
        flux,
        color: Vec3::ONE,
    };
    let camera = Camera {
        position: Vec3::new(0.0, 3.0, 0.5),
        target: Vec3::ZERO,
        up: Vec3::Y,
        vfov_deg: 50.0,
    };
    Scene::new("plane".into(), mesh, vec![material], vec![light], camera).unwrap()
}

/// Render `frames` frames of `scene` with LPV `settings` and return the linear HDR pixels.
pub fn render_gi(
    gpu: &Gpu,
    scene: &Scene,
    settings: vkgi::gi::lpv::LpvSettings,
    options: FrameOptions,
    frames: u32,
) -> Vec<[f32; 3]> {
    let setup = vkgi::gi::registry::Setup::new(gpu, scene);
    let mut lpv = vkgi::gi::lpv::Lpv::new(&setup, settings).expect("lpv");
    render_with(gpu, scene, &mut lpv, options, frames)
}

/// Render `frames` frames of `scene` with a GI method and return the linear HDR pixels.
pub fn render_with(
    gpu: &Gpu,
    scene: &Scene,
    method: &mut dyn vkgi::gi::GiMethod,
    options: FrameOptions,
    frames: u32,
) -> Vec<[f32; 3]> {
    let mut frame = Frame::new(gpu, scene, options).expect("frame");
    let ring =
        vkgi::render::runner::run_frames(gpu, &mut frame, Some(method), 0, frames).expect("frames");
    drop(ring);
    frame.read_hdr(gpu).expect("readback")
}

/// Frame options for an indirect-only image of the given size.
pub fn indirect_only(width: u32, height: u32) -> FrameOptions {
    FrameOptions {
        width,
        height,
        indirect_only: true,
        ..FrameOptions::default()
    }
}

pub fn mean(pixels: &[[f32; 3]]) -> f64 {
    pixels.iter().map(|p| f64::from(luminance(*p))).sum::<f64>() / pixels.len() as f64
}
