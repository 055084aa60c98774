//! glTF 2.0 scenes: one scene (a textured floor, a block under a node transform, a spot light
//! and a camera) written by this test both as glTF (`.gltf` with an external buffer and image,
//! and `.glb` with everything embedded) and, transformed and converted by hand from the glTF
//! specification's definitions, as OBJ + MTL + TOML. vkgi must render the two identically.

use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};
use serde_json::json;
use vkgi::gi::registry::{self, Setup};
use vkgi::reference::{Bounces, PathTracer, ReferenceSettings};
use vkgi::render::FrameOptions;
use vkgi::scene::{LightKind, Scene};

mod common;

const CANDELA: f32 = 40.0;
const INNER: f32 = 0.7;
const OUTER: f32 = 1.1;
const LIGHT_COLOR: [f32; 3] = [1.0, 0.9, 0.8];
const YFOV: f32 = 0.75;

/// Floor: a unit quad in its node's frame (the node scales it by 2 in x and z), texture
/// coordinates 0..2 (the 4x4 texture repeats twice).
const FLOOR: [[f32; 3]; 4] = [
    [-0.5, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.5, 0.0, -0.5],
    [-0.5, 0.0, -0.5],
];
const FLOOR_UV: [[f32; 2]; 4] = [[0.0, 2.0], [2.0, 2.0], [2.0, 0.0], [0.0, 0.0]];
const FLOOR_INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];
const FLOOR_SCALE: [f32; 3] = [2.0, 1.0, 2.0];

/// Block half-sizes (the node turns it 90° about y and moves it).
const BLOCK_HALF: [f32; 3] = [0.3, 0.25, 0.125];

/// The block node: 90° about y (x → -z, z → x), then moved by (0.25, 0.25, -0.25).
fn block_matrix() -> Mat4 {
    Mat4::from_cols_array(&[
        0.0, 0.0, -1.0, 0.0, //
        0.0, 1.0, 0.0, 0.0, //
        1.0, 0.0, 0.0, 0.0, //
        0.25, 0.25, -0.25, 1.0,
    ])
}

/// The light node: -z turned to -y (90° about x), at (0, 1.75, 0).
fn light_matrix() -> Mat4 {
    Mat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, -1.0, 0.0, //
        0.0, 1.0, 0.0, 0.0, //
        0.0, 1.75, 0.0, 1.0,
    ])
}

const CAMERA_AT: [f32; 3] = [0.0, 1.6, 2.2];
/// The camera node turns the view down by this angle (radians) about x, onto the floor.
const CAMERA_PITCH: f32 = 0.63;

fn camera_rotation() -> Quat {
    Quat::from_rotation_x(-CAMERA_PITCH)
}

/// The block's corners and outward triangles (counter-clockwise seen from outside).
fn block() -> (Vec<[f32; 3]>, Vec<u16>) {
    let [x, y, z] = BLOCK_HALF;
    let corners: Vec<[f32; 3]> = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { -x } else { x },
                if i & 2 == 0 { -y } else { y },
                if i & 4 == 0 { -z } else { z },
            ]
        })
        .collect();
    let quads = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let indices = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [a, b, c, a, c, d])
        .collect();
    (corners, indices)
}

/// A 4x4 texture of distinct colours, as PNG bytes.
fn texture_png() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(4, 4, |x, y| {
        let i = (y * 4 + x).wrapping_mul(0x9E37_79B9) >> 8;
        image::Rgba([i as u8, (i >> 8) as u8, (i >> 16) as u8, 255])
    });
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-gltf-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The binary buffer and the glTF JSON describing it. With `embed_image` the PNG is a buffer
/// view; otherwise the JSON names `texture.png` beside the file.
fn gltf_document(embed_image: bool, buffer_uri: Option<&str>) -> (serde_json::Value, Vec<u8>) {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: &[u8], target: Option<u32>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        let mut view = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        views.push(view);
        views.len() - 1
    };
    let floats =
        |v: &[[f32; 3]]| -> Vec<u8> { v.iter().flatten().flat_map(|f| f.to_le_bytes()).collect() };
    let (block_corners, block_indices) = block();
    let shorts = |v: &[u16]| -> Vec<u8> { v.iter().flat_map(|s| s.to_le_bytes()).collect() };
    let floor_position = push(&floats(&FLOOR), Some(34962));
    let floor_normal = push(&floats(&[[0.0, 1.0, 0.0]; 4]), Some(34962));
    let uv: Vec<u8> = FLOOR_UV
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let floor_uv = push(&uv, Some(34962));
    let floor_index = push(&shorts(&FLOOR_INDICES), Some(34963));
    let block_position = push(&floats(&block_corners), Some(34962));
    let block_index = push(&shorts(&block_indices), Some(34963));
    let image = if embed_image {
        let view = push(&texture_png(), None);
        json!({"bufferView": view, "mimeType": "image/png"})
    } else {
        json!({"uri": "texture.png"})
    };
    let bounds = |v: &[[f32; 3]]| {
        let min = (0..3)
            .map(|k| v.iter().map(|p| p[k]).fold(f32::MAX, f32::min))
            .collect::<Vec<_>>();
        let max = (0..3)
            .map(|k| v.iter().map(|p| p[k]).fold(f32::MIN, f32::max))
            .collect::<Vec<_>>();
        (min, max)
    };
    let (floor_min, floor_max) = bounds(&FLOOR);
    let (block_min, block_max) = bounds(&block_corners);
    let mut buffer = json!({"byteLength": bin.len()});
    if let Some(uri) = buffer_uri {
        buffer["uri"] = json!(uri);
    }
    let document = json!({
        "asset": {"version": "2.0", "generator": "vkgi tests/gltf.rs"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{
            "type": "spot", "color": LIGHT_COLOR, "intensity": CANDELA,
            "spot": {"innerConeAngle": INNER, "outerConeAngle": OUTER}
        }]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0, "scale": FLOOR_SCALE},
            {"mesh": 1, "matrix": block_matrix().to_cols_array()},
            {"matrix": light_matrix().to_cols_array(),
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"camera": 0, "translation": CAMERA_AT,
             "rotation": camera_rotation().to_array()}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": YFOV, "znear": 0.01}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                             "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 4}, "indices": 5, "material": 1}]}
        ],
        "materials": [
            {"name": "floor", "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 0.9, 0.8, 1.0], "baseColorTexture": {"index": 0},
                "metallicFactor": 0.0}},
            {"name": "block", "pbrMetallicRoughness": {
                "baseColorFactor": [0.6, 0.3, 0.2, 1.0], "metallicFactor": 0.0}}
        ],
        "textures": [{"source": 0}],
        "images": [image],
        "accessors": [
            {"bufferView": floor_position, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": floor_min, "max": floor_max},
            {"bufferView": floor_normal, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": floor_uv, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": floor_index, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": block_position, "componentType": 5126, "count": 8, "type": "VEC3",
             "min": block_min, "max": block_max},
            {"bufferView": block_index, "componentType": 5123, "count": block_indices.len(),
             "type": "SCALAR"}
        ],
        "bufferViews": views,
        "buffers": [buffer]
    });
    (document, bin)
}

/// `.gltf` + `scene.bin` + `texture.png`.
fn write_gltf(dir: &Path) -> PathBuf {
    let (document, bin) = gltf_document(false, Some("scene.bin"));
    std::fs::write(dir.join("scene.bin"), bin).unwrap();
    std::fs::write(dir.join("texture.png"), texture_png()).unwrap();
    let path = dir.join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
    path
}

/// A `.glb`: JSON and binary chunks, the image inside the binary one.
fn write_glb(dir: &Path) -> PathBuf {
    let (document, mut bin) = gltf_document(true, None);
    let mut text = serde_json::to_vec(&document).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(text.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&text);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    let path = dir.join("scene.glb");
    std::fs::write(&path, glb).unwrap();
    path
}

/// The same scene as OBJ + MTL + TOML, every transform and unit conversion done here from the
/// glTF specification: node matrices applied to the vertices, v flipped (OBJ's v runs up the
/// image), the spot's candela turned into W/sr at 683 lm/W and into the flux of vkgi's spot
/// profile (peak intensity times the profile's solid angle), cone half-angles in degrees.
fn write_obj_toml(dir: &Path) -> PathBuf {
    std::fs::write(dir.join("texture.png"), texture_png()).unwrap();
    let mut obj = String::from("mtllib scene.mtl\n");
    let scale = Vec3::from(FLOOR_SCALE);
    for p in FLOOR {
        let p = Vec3::from(p) * scale;
        obj += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for [u, v] in FLOOR_UV {
        obj += &format!("vt {} {}\n", u, 1.0 - v);
    }
    obj += "vn 0 1 0\nusemtl floor\n";
    for t in FLOOR_INDICES.chunks(3) {
        let c: Vec<String> = t.iter().map(|&i| format!("{0}/{0}/1", i + 1)).collect();
        obj += &format!("f {}\n", c.join(" "));
    }
    let (corners, indices) = block();
    for p in &corners {
        // The block matrix by hand: (x, y, z) -> (z, y, -x) + (0.25, 0.25, -0.25).
        let [x, y, z] = *p;
        obj += &format!("v {} {} {}\n", z + 0.25, y + 0.25, -x - 0.25);
    }
    obj += "usemtl block\n";
    for t in indices.chunks(3) {
        let c: Vec<String> = t.iter().map(|&i| format!("{}", i + 5)).collect();
        obj += &format!("f {}\n", c.join(" "));
    }
    std::fs::write(dir.join("scene.obj"), obj).unwrap();
    let mtl = "newmtl floor\nKd 1 0.9 0.8\nmap_Kd texture.png\nnewmtl block\nKd 0.6 0.3 0.2\n";
    std::fs::write(dir.join("scene.mtl"), mtl).unwrap();
    let (cos_outer, cos_inner) = (f64::from(OUTER).cos(), f64::from(INNER).cos());
    let solid_angle =
        2.0 * std::f64::consts::PI * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 3.0);
    let flux = f64::from(CANDELA) / 683.0 * solid_angle;
    let [cx, cy, cz] = CAMERA_AT;
    let target = Vec3::from(CAMERA_AT) + camera_rotation() * Vec3::NEG_Z;
    let up = camera_rotation() * Vec3::Y;
    let toml = format!(
        "mesh = \"scene.obj\"\n\
         [camera]\nposition = [{cx}, {cy}, {cz}]\ntarget = [{}, {}, {}]\nup = [{}, {}, {}]\nfov = {}\n\
         [[light]]\ntype = \"spot\"\nposition = [0, 1.75, 0]\ndirection = [0, -1, 0]\n\
         cone_angle = {}\npenumbra = {}\nflux = {flux}\ncolor = [{}, {}, {}]\n",
        target.x,
        target.y,
        target.z,
        up.x,
        up.y,
        up.z,
        f64::from(YFOV).to_degrees(),
        f64::from(OUTER).to_degrees(),
        f64::from(OUTER - INNER).to_degrees(),
        LIGHT_COLOR[0],
        LIGHT_COLOR[1],
        LIGHT_COLOR[2],
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

#[test]
fn gltf_reads_transforms_units_textures_lights_and_the_camera() {
    let dir = scratch("read");
    for path in [write_gltf(&dir), write_glb(&dir)] {
        let scene = Scene::load(path.to_str().unwrap()).unwrap();
        assert_eq!(scene.mesh.triangle_count(), 2 + 12, "{}", path.display());
        let size = scene.bounds_max - scene.bounds_min;
        assert!((size - Vec3::new(2.0, 0.5, 2.0)).length() < 1e-6, "{size}");
        let floor = &scene.materials[scene.mesh.materials[0] as usize];
        let texture = floor.albedo_texture.as_ref().expect("a textured floor");
        assert_eq!((texture.width, texture.height), (4, 4));
        let light = &scene.lights[0];
        assert_eq!(light.position, Vec3::new(0.0, 1.75, 0.0));
        let LightKind::Spot {
            direction,
            cone_angle_deg,
            penumbra_deg,
        } = light.kind
        else {
            panic!("a spot light")
        };
        assert!((direction - Vec3::NEG_Y).length() < 1e-6);
        assert!((cone_angle_deg - OUTER.to_degrees()).abs() < 1e-4);
        assert!((penumbra_deg - (OUTER - INNER).to_degrees()).abs() < 1e-4);
        // The peak intensity is the candela at 683 lm/W, per channel tinted by the colour.
        let peak = light.intensity();
        for (c, k) in peak.to_array().iter().zip(LIGHT_COLOR) {
            assert!((c - CANDELA / 683.0 * k).abs() < 1e-6 * c, "{peak}");
        }
        assert_eq!(scene.camera.position, Vec3::from(CAMERA_AT));
        let forward = (scene.camera.target - scene.camera.position).normalize();
        let expected = Vec3::new(0.0, -CAMERA_PITCH.sin(), -CAMERA_PITCH.cos());
        assert!((forward - expected).length() < 1e-6, "{forward}");
        assert!((scene.camera.vfov_deg - YFOV.to_degrees()).abs() < 1e-4);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Worst per-pixel difference of `a` from `b`, relative to `b`'s brightest value, and the
/// worst relative to each pixel itself (where it is above 1% of the brightest).
fn differences(a: &[[f32; 3]], b: &[[f32; 3]]) -> (f32, f32) {
    let peak = b.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
    let lit = b
        .iter()
        .filter(|p| p.iter().any(|&c| c > 0.01 * peak))
        .count();
    assert!(
        peak > 0.0 && lit * 4 > b.len(),
        "the image must be lit to compare it: peak {peak}, {lit} of {} pixels lit",
        b.len()
    );
    let mut of_peak = 0.0f32;
    let mut of_pixel = 0.0f32;
    for (p, q) in a.iter().flatten().zip(b.iter().flatten()) {
        let d = (p - q).abs();
        of_peak = of_peak.max(d / peak);
        if *q > 0.01 * peak {
            of_pixel = of_pixel.max(d / q);
        }
    }
    (of_peak, of_pixel)
}

#[test]
fn a_gltf_scene_renders_as_the_same_scene_written_as_obj_and_toml() {
    let gpu = common::gpu();
    let dir = scratch("equal");
    let obj = Scene::load(write_obj_toml(&dir).to_str().unwrap()).unwrap();
    let (w, h) = (64, 48);
    for path in [write_gltf(&dir), write_glb(&dir)] {
        let gltf = Scene::load(path.to_str().unwrap()).unwrap();
        let mut images = vec![(
            "direct light",
            common::render(&gpu, &gltf, w, h).1,
            common::render(&gpu, &obj, w, h).1,
        )];
        for entry in registry::methods() {
            let render = |scene: &Scene| {
                let settings = entry.settings(&[]).unwrap();
                let mut method = entry.create(&Setup::new(&gpu, scene), &settings).unwrap();
                let options = FrameOptions {
                    width: w,
                    height: h,
                    ..FrameOptions::default()
                };
                common::render_with(&gpu, scene, method.as_mut(), options, 4)
            };
            images.push((entry.name, render(&gltf), render(&obj)));
        }
        let settings = ReferenceSettings {
            strategy: Default::default(),
            width: w,
            height: h,
            spp: 4,
            bounces: Bounces::Limited(2),
            seed: 3,
        };
        let trace = |scene: &Scene| {
            let mut tracer = PathTracer::new(&gpu, scene, w, h).unwrap();
            let images = tracer.render(&gpu, &settings, |_, _| {}).unwrap();
            images.combined().pixels
        };
        images.push(("path tracer", trace(&gltf), trace(&obj)));
        for (what, a, b) in &images {
            let (of_peak, of_pixel) = differences(a, b);
            eprintln!(
                "{} {what}: worst difference {of_peak:.2e} of the peak, {of_pixel:.2e} of the pixel",
                path.display()
            );
            assert!(
                of_peak <= 1e-3 && of_pixel <= 1e-3,
                "{what}: glTF and OBJ+TOML differ by {of_peak:.2e} of the peak, {of_pixel:.2e} of a pixel"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
    std::fs::remove_dir_all(&dir).unwrap();
}
