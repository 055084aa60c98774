//! `vkgi scene`: the list of built-in scenes, and every scene written as OBJ + MTL + PNG +
//! scene file reads back as the same scene — triangle by triangle, material by material, light
//! by light — so it renders the same (checked once more by rendering a textured glTF both ways).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use vkgi::reference::{Bounces, PathTracer, ReferenceSettings};
use vkgi::scene::Scene;
use vkgi::scene::builtin;

mod common;

fn vkgi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(args)
        .output()
        .expect("the vkgi binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-export-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `vkgi scene SPEC --write DIR`, then the written scene file read back.
fn write_and_read(spec: &str, dir: &Path) -> Scene {
    let output = vkgi(&["scene", spec, "--write", dir.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{spec}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let scene_file = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "toml"))
        .expect("a scene file");
    Scene::load(scene_file.to_str().unwrap()).unwrap()
}

/// Why `b` is not the scene `a` is, if it is not.
fn difference(a: &Scene, b: &Scene) -> Option<String> {
    if a.mesh.triangle_count() != b.mesh.triangle_count() {
        return Some(format!(
            "{} triangles, read back {}",
            a.mesh.triangle_count(),
            b.mesh.triangle_count()
        ));
    }
    for t in 0..a.mesh.triangle_count() {
        let corners = |s: &Scene| s.mesh.indices[t].map(|i| i as usize);
        let (ca, cb) = (corners(a), corners(b));
        for (&i, &j) in ca.iter().zip(&cb) {
            if a.mesh.positions[i] != b.mesh.positions[j] || a.mesh.normals[i] != b.mesh.normals[j]
            {
                return Some(format!("triangle {t}: a corner's position or normal"));
            }
            let textured = a.materials[a.mesh.materials[t] as usize]
                .albedo_texture
                .is_some();
            if textured
                && (a.mesh.texcoords[i] - b.mesh.texcoords[j])
                    .abs()
                    .max_element()
                    > 1e-6
            {
                return Some(format!(
                    "triangle {t}: texture coordinates {} read back as {}",
                    a.mesh.texcoords[i], b.mesh.texcoords[j]
                ));
            }
        }
        let (ma, mb) = (
            &a.materials[a.mesh.materials[t] as usize],
            &b.materials[b.mesh.materials[t] as usize],
        );
        if (ma.albedo, ma.emission, ma.two_sided) != (mb.albedo, mb.emission, mb.two_sided) {
            return Some(format!("triangle {t}: material {ma:?} read back as {mb:?}"));
        }
        match (&ma.albedo_texture, &mb.albedo_texture) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                let rgb = |t: &vkgi::scene::Texture| -> Vec<u32> {
                    t.texels.iter().map(|v| v & 0x00FF_FFFF).collect()
                };
                if (x.width, x.height, rgb(x)) != (y.width, y.height, rgb(y)) {
                    return Some(format!("triangle {t}: texture texels"));
                }
            }
            _ => return Some(format!("triangle {t}: a texture gained or lost")),
        }
    }
    if a.lights != b.lights {
        return Some(format!("lights {:?} read back as {:?}", a.lights, b.lights));
    }
    let paths = |s: &Scene| -> Vec<(String, vkgi::scene::dynamic::Path)> {
        s.dynamic
            .iter()
            .map(|o| (o.name.clone(), o.path.clone()))
            .collect()
    };
    if paths(a) != paths(b) {
        return Some(format!(
            "dynamic objects {:?} read back as {:?}",
            paths(a),
            paths(b)
        ));
    }
    let (ca, cb) = (&a.camera, &b.camera);
    if (ca.position, ca.target, ca.vfov_deg) != (cb.position, cb.target, cb.vfov_deg)
        || ca.up.normalize().dot(cb.up.normalize()) < 1.0 - 1e-6
    {
        return Some(format!("camera {ca:?} read back as {cb:?}"));
    }
    None
}

#[test]
fn scene_list_names_every_builtin_scene() {
    let output = vkgi(&["scene", "--list"]);
    assert!(output.status.success());
    let listed = String::from_utf8(output.stdout).unwrap();
    for (name, _) in builtin::catalogue() {
        assert!(
            listed
                .lines()
                .any(|l| l.split_whitespace().next() == Some(name)),
            "{name} missing from: {listed}"
        );
    }
}

#[test]
fn every_builtin_scene_written_as_files_reads_back_as_the_same_scene() {
    for (name, _) in builtin::catalogue() {
        // The full atrium is the same code at a larger detail; detail 1 keeps the test quick.
        let spec = if name == "atrium" { "atrium:1" } else { name };
        let dir = scratch(name);
        let mut read_back = write_and_read(spec, &dir);
        let mut original = Scene::load(spec).unwrap();
        if let Some(why) = difference(&original, &read_back) {
            panic!("{spec}: {why}");
        }
        // Dynamic objects follow the same paths from the same places.
        if !original.dynamic.is_empty() {
            original.pose(37);
            read_back.pose(37);
            if let Some(why) = difference(&original, &read_back) {
                panic!("{spec} at frame 37: {why}");
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_textured_gltf_written_as_files_renders_the_same() {
    let dir = scratch("gltf");
    std::fs::create_dir_all(&dir).unwrap();
    let gltf_path = common::gltf_fixture::write_gltf(&dir);
    let original = Scene::load(gltf_path.to_str().unwrap()).unwrap();
    let read_back = write_and_read(gltf_path.to_str().unwrap(), &dir.join("written"));
    if let Some(why) = difference(&original, &read_back) {
        panic!("glTF fixture: {why}");
    }
    let gpu = common::gpu();
    let (w, h) = (48, 36);
    let settings = ReferenceSettings {
        strategy: Default::default(),
        width: w,
        height: h,
        spp: 2,
        bounces: Bounces::Limited(2),
        seed: 5,
    };
    let trace = |scene: &Scene| {
        let mut tracer = PathTracer::new(&gpu, scene, w, h).unwrap();
        tracer
            .render(&gpu, &settings, |_, _| {})
            .unwrap()
            .combined()
            .pixels
    };
    let renders = [
        (
            common::render(&gpu, &original, w, h).1,
            common::render(&gpu, &read_back, w, h).1,
        ),
        (trace(&original), trace(&read_back)),
    ];
    for (a, b) in &renders {
        let (worst, peak) = common::worst_difference(a, b);
        assert!(
            peak > 0.0 && worst <= 1e-3 * peak,
            "worst {worst} of peak {peak}"
        );
    }
    common::assert_no_validation_errors(&gpu);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scene_without_an_action_or_onto_a_file_is_bad_input() {
    let dir = scratch("bad");
    std::fs::create_dir_all(&dir).unwrap();
    assert_eq!(vkgi(&["scene"]).status.code(), Some(2));
    assert_eq!(vkgi(&["scene", "cornell"]).status.code(), Some(2));
    let file = dir.join("file");
    std::fs::write(&file, "x").unwrap();
    let output = vkgi(&["scene", "cornell", "--write", file.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("not a folder"));
    let output = vkgi(&["scene", "no-such-scene", "--write", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
