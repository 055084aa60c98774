//! Helpers shared by the integration tests: a validated GPU and one-frame renders.
#![allow(dead_code)]

pub mod cli;
pub mod fuzzing;
pub mod gltf_fixture;

use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions, PixelPasses};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

/// A GPU context with the Khronos validation layers (synchronization validation included).
pub fn gpu() -> Gpu {
    gpu_with(None)
}

/// [`gpu`] running the per-pixel passes with two forms as `pixel_passes` (None: the device's
/// own choice).
pub fn gpu_with(pixel_passes: Option<PixelPasses>) -> Gpu {
    Gpu::new(&GpuOptions {
        validation: true,
        device: None,
        display: None,
        pixel_passes,
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
        emission: Vec3::splat(emission),
        // The camera sees the enclosure from inside, against its outward winding.
        two_sided: true,
        ..Material::diffuse("furnace", Vec3::splat(albedo))
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
    let material = Material::diffuse("plane", Vec3::splat(albedo));
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

/// `plane_under_point_light` with a 4x4 texture of distinct colours on the plane, repeated
/// twice across it (texture coordinates -0.5 to 1.5 from corner to corner).
pub fn textured_plane_under_point_light(flux: f32) -> Scene {
    let mut scene = plane_under_point_light(1.0, flux);
    for (p, uv) in scene.mesh.positions.iter().zip(&mut scene.mesh.texcoords) {
        *uv = glam::Vec2::new(p.x, p.z) * 0.5 + 0.5;
    }
    let texels = (0..16u32)
        .map(|i| {
            let h = i.wrapping_mul(0x9E37_79B9) >> 8;
            (h & 0xff) | (((h >> 8) & 0xff) << 8) | (((h >> 16) & 0xff) << 16) | 0xff << 24
        })
        .collect();
    let texture = vkgi::scene::Texture::new("checker", 4, 4, texels).unwrap();
    scene.materials[0].albedo = Vec3::new(1.0, 0.9, 0.8);
    scene.materials[0].albedo_texture = Some(std::sync::Arc::new(texture));
    Scene::new(
        "textured plane".into(),
        scene.mesh,
        scene.materials,
        scene.lights,
        scene.camera,
    )
    .unwrap()
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

/// Run `frames` frames (no warm-up) of `frame` with a GI method; the names of the passes the
/// profiler timed, in its report's order.
pub fn run_naming_passes(
    gpu: &Gpu,
    frame: &mut Frame,
    method: &mut dyn vkgi::gi::GiMethod,
    frames: u32,
) -> Vec<String> {
    let ring =
        vkgi::render::runner::run_frames(gpu, frame, Some(method), 0, frames).expect("frames");
    let report = ring.profiler.report();
    report.passes.iter().map(|p| p.name.clone()).collect()
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

/// The largest per-channel difference between two images, and `b`'s brightest value.
pub fn worst_difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> (f32, f32) {
    let peak = b.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
    let worst = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f32, f32::max);
    (worst, peak)
}

pub fn mean(pixels: &[[f32; 3]]) -> f64 {
    pixels.iter().map(|p| f64::from(luminance(*p))).sum::<f64>() / pixels.len() as f64
}

/// A 4 m Lambertian floor (albedo `albedo`) at y = 0 and, `height` above its centre, a square
/// emitter of side `side` facing down (one-sided) with radiance `le`; seen from the side.
pub fn plane_under_square_light(albedo: f32, side: f32, height: f32, le: f32) -> Scene {
    let mut mesh = Mesh::default();
    let quad = |mesh: &mut Mesh, corners: [Vec3; 4], material: u32| {
        for tri in [[0, 1, 2], [0, 2, 3]] {
            mesh.push_triangle(tri.map(|i| corners[i]), [Vec3::ZERO; 3], material);
        }
    };
    let floor =
        [(-2.0, -2.0), (-2.0, 2.0), (2.0, 2.0), (2.0, -2.0)].map(|(x, z)| Vec3::new(x, 0.0, z));
    quad(&mut mesh, floor, 0);
    let r = 0.5 * side;
    // Winding (-x,-z) -> (r,-z) -> (r,z): its normal points down, toward the floor.
    let light = [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, z)| Vec3::new(x, height, z));
    quad(&mut mesh, light, 1);
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(albedo)),
        Material {
            emission: Vec3::splat(le),
            ..Material::diffuse("light", Vec3::ZERO)
        },
    ];
    let camera = Camera {
        position: Vec3::new(0.0, 0.45 * height, 2.5),
        target: Vec3::new(0.0, 0.0, -0.3),
        up: Vec3::Y,
        vfov_deg: 60.0,
    };
    Scene::new("square light".into(), mesh, materials, vec![], camera).unwrap()
}

/// Irradiance at floor point `p` (y = 0) from a square emitter of side `side` and radiance
/// `le` parallel to the floor `height` above the origin: the closed form of a parallel
/// rectangle, summed over the four rectangles that meet at the point below `p`.
pub fn square_light_irradiance(p: Vec3, side: f32, height: f32, le: f32) -> f64 {
    let h = f64::from(height);
    // ∫∫ over [0,a]x[0,b] of h² / (h² + u² + v²)² du dv.
    let corner = |a: f64, b: f64| {
        let (x, y) = (a / h, b / h);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
    };
    let signed = |u: f64, v: f64| u.signum() * v.signum() * corner(u.abs(), v.abs());
    let r = 0.5 * f64::from(side);
    let (x0, x1) = (-r - f64::from(p.x), r - f64::from(p.x));
    let (z0, z1) = (-r - f64::from(p.z), r - f64::from(p.z));
    f64::from(le) * (signed(x1, z1) - signed(x0, z1) - signed(x1, z0) + signed(x0, z0))
}

/// An IEEE half-precision float's value (G-buffer normals, RSM texels read back).
pub fn half_to_f32(bits: u16) -> f32 {
    let sign = if bits >> 15 == 1 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    match exponent {
        0 => sign * mantissa * 2f32.powi(-24),
        31 => sign * f32::INFINITY,
        e => sign * (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}
