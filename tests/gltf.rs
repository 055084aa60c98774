//! glTF 2.0 scenes: one scene (a textured floor, a block under a node transform, a spot light
//! and a camera) written by this test both as glTF (`.gltf` with an external buffer and image,
//! and `.glb` with everything embedded) and, transformed and converted by hand from the glTF
//! specification's definitions, as OBJ + MTL + TOML. vkgi must render the two identically.

use std::path::{Path, PathBuf};

use glam::Vec3;
use vkgi::gi::registry::{self, Setup};
use vkgi::reference::{Bounces, PathTracer, ReferenceSettings};
use vkgi::render::FrameOptions;
use vkgi::scene::{LightKind, Scene};

mod common;

use common::gltf_fixture::*;

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
    // Dielectrics (metallic 0, roughness 1 by default): a glossy lobe of 0.04, lowered where
    // albedo + lobe would pass 1, and roughness 1 (Ns 0).
    let mtl = "newmtl floor\nKd 1 0.9 0.8\nKs 0 0.04 0.04\nNs 0\nmap_Kd texture.png\n\
               newmtl block\nKd 0.6 0.3 0.2\nKs 0.04 0.04 0.04\nNs 0\n";
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

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-gltf-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
