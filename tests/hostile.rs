//! Regression tests for every failure a hostile-input pass found (one test per finding, named
//! after it), end to end through the binary: bad input gets one line and exit code 2, never a
//! panic, a non-finite image or a silent black one; outputs go only to regular files.

use std::path::PathBuf;
use std::process::{Command, Output};

use common::gltf_fixture::{glb_bytes, gltf_document};
use serde_json::json;

mod common;

use common::cli::{assert_bad_input, vkgi, write};

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    common::cli::scratch("hostile", name)
}

const QUAD: &str = "mtllib m.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl grey\nf 1 2 3 4\n";
const MTL: &str = "newmtl grey\nKd 0.5 0.5 0.5\n";

/// A scene folder with the quad, its MTL and a scene file whose light (and camera) are
/// `light` (and `camera`) TOML.
fn scene_with(name: &str, light: &str, camera: &str, scale: &str) -> (PathBuf, String) {
    let dir = scratch(name);
    write(&dir, "quad.obj", QUAD);
    write(&dir, "m.mtl", MTL);
    let camera = if camera.is_empty() {
        "[camera]\nposition = [0, 2, 3]\ntarget = [0, 0, 0]\nfov = 50\n"
    } else {
        camera
    };
    let toml = format!("mesh = \"quad.obj\"\nscale = {scale}\n{camera}\n[[light]]\n{light}\n");
    let scene = write(&dir, "scene.toml", &toml);
    (dir, scene)
}

const POINT: &str = "type = \"point\"\nposition = [0, 1, 0]\nflux = 10\n";

fn render(scene: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "render", "--scene", scene, "--size", "16x12", "--method", "none",
    ];
    args.extend_from_slice(extra);
    vkgi(&args)
}

#[test]
fn an_mtl_colour_line_with_fewer_than_three_numbers_is_an_error_not_a_panic() {
    for line in ["Kd 0.5", "Ka 0.1 0.2", "Ks", "Ke 1 1", "Kd 0"] {
        let dir = scratch("short-colour");
        write(&dir, "quad.obj", QUAD);
        write(&dir, "m.mtl", &format!("newmtl grey\n{line}"));
        let obj = dir.join("quad.obj");
        assert_bad_input(&render(obj.to_str().unwrap(), &[]), "needs three numbers");
    }
}

#[test]
fn flux_times_color_overflowing_is_refused() {
    let (_, scene) = scene_with(
        "flux",
        "type = \"point\"\nposition = [0, 1, 0]\nflux = 3e38\n",
        "",
        "1",
    );
    assert_bad_input(&render(&scene, &[]), "limit");
    let (_, scene) = scene_with(
        "color",
        "type = \"point\"\nposition = [0, 1, 0]\nflux = 1\ncolor = [1e38, 1, 1]\n",
        "",
        "1",
    );
    assert_bad_input(&render(&scene, &[]), "limit");
}

#[test]
fn a_spot_direction_of_1e38_is_normalised_not_zeroed() {
    let spot = "type = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1e38, 0]\ncone_angle = 60\npenumbra = 5\nflux = 10\n";
    let (dir, scene) = scene_with("spot", spot, "", "1");
    let hdr = dir.join("lit.exr");
    let output = render(&scene, &["--hdr", hdr.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let image = vkgi::imageio::read_hdr(&hdr, false).unwrap();
    let brightest = image.pixels.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
    assert!(brightest > 0.0, "the quad is lit");
}

#[test]
fn positions_near_1e38_and_a_scale_of_1e30_are_refused() {
    let (_, scene) = scene_with(
        "light-far",
        "type = \"point\"\nposition = [1e38, 1, 0]\nflux = 1\n",
        "",
        "1",
    );
    assert_bad_input(&render(&scene, &[]), "light 1");
    let camera = "[camera]\nposition = [1e38, 2, 3]\ntarget = [0, 0, 0]\nfov = 50\n";
    let (_, scene) = scene_with("camera-far", POINT, camera, "1");
    assert_bad_input(&render(&scene, &[]), "camera");
    let (_, scene) = scene_with("scale", POINT, "", "1e30");
    assert_bad_input(&render(&scene, &[]), "mesh reaches");
}

#[test]
fn absurd_offsets_are_out_of_range() {
    for (flag, value) in [
        ("--inject-offset", "1e30"),
        ("--lookup-offset", "NaN"),
        ("--lookup-offset", "1e30"),
    ] {
        let output = vkgi(&["render", "--size", "16x12", flag, value]);
        assert_bad_input(&output, "out of range");
    }
}

#[test]
fn report_with_zero_frames_is_refused() {
    let dir = scratch("report-frames");
    let output = vkgi(&[
        "report",
        "--out-dir",
        dir.to_str().unwrap(),
        "--frames",
        "0",
    ]);
    assert_bad_input(&output, "--frames");
}

#[test]
fn frame_counts_that_would_run_for_days_are_refused() {
    // Each measured frame keeps its passes' times until the run ends: four billion of them
    // were taken, to run for months with their samples growing. Refused before any GPU work,
    // with the range in the line (a missing scene after the count: were the count taken, the
    // line would name the scene).
    let dir = scratch("frame-counts");
    let out_dir = dir.to_str().unwrap();
    for (command, flag) in [
        ("render", "--frames"),
        ("report", "--frames"),
        ("profile", "--frames"),
        ("profile", "--warmup"),
    ] {
        for count in ["4000000000", "100001"] {
            let mut args = vec![command, flag, count, "--scene", "/nonexistent/scene.obj"];
            if command == "report" {
                args.extend(["--out-dir", out_dir]);
            }
            let output = vkgi(&args);
            assert_bad_input(&output, &format!("{flag} <"));
            assert_bad_input(&output, "..=100000");
        }
    }
}

#[test]
fn a_camera_position_with_four_elements_is_refused() {
    let camera = "[camera]\nposition = [0, 2, 3, 4]\ntarget = [0, 0, 0]\nfov = 50\n";
    let (_, scene) = scene_with("camera4", POINT, camera, "1");
    assert_bad_input(&render(&scene, &[]), "expected 3 numbers");
}

#[test]
fn usemtl_of_a_missing_material_is_refused() {
    let dir = scratch("usemtl");
    write(
        &dir,
        "quad.obj",
        &QUAD.replace("usemtl grey", "usemtl gray"),
    );
    write(&dir, "m.mtl", MTL);
    let obj = dir.join("quad.obj");
    assert_bad_input(&render(obj.to_str().unwrap(), &[]), "usemtl gray");
}

#[test]
fn a_two_vertex_face_is_refused() {
    let dir = scratch("face2");
    let obj = write(
        &dir,
        "two.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n",
    );
    assert_bad_input(&render(&obj, &[]), "at least 3 vertices");
}

#[test]
fn out_o_jpg_writes_jpeg_and_other_extensions_are_refused() {
    let dir = scratch("jpeg");
    let jpg = dir.join("o.jpg");
    let output = vkgi(&[
        "render",
        "--size",
        "16x12",
        "--method",
        "none",
        "--out",
        jpg.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(
        &std::fs::read(&jpg).unwrap()[..2],
        &[0xFF, 0xD8],
        "JPEG bytes"
    );
    let bmp = dir.join("o.bmp");
    assert_bad_input(
        &vkgi(&["render", "--size", "16x12", "--out", bmp.to_str().unwrap()]),
        "png",
    );
    let hdr = dir.join("o.png");
    assert_bad_input(
        &vkgi(&["render", "--size", "16x12", "--hdr", hdr.to_str().unwrap()]),
        "exr",
    );
}

#[test]
fn compare_refuses_tone_mapped_images_unless_allowed() {
    let dir = scratch("compare-ldr");
    let png = dir.join("t.png");
    let exr = dir.join("r.exr");
    let output = vkgi(&[
        "render",
        "--size",
        "16x12",
        "--method",
        "none",
        "--out",
        png.to_str().unwrap(),
        "--hdr",
        exr.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    assert_bad_input(
        &vkgi(&["compare", png.to_str().unwrap(), exr.to_str().unwrap()]),
        "--allow-ldr",
    );
    let allowed = vkgi(&[
        "compare",
        png.to_str().unwrap(),
        exr.to_str().unwrap(),
        "--allow-ldr",
    ]);
    assert!(
        allowed.status.success(),
        "{}",
        String::from_utf8_lossy(&allowed.stderr)
    );
}

#[test]
fn negative_numbers_get_a_range_message() {
    assert_bad_input(&vkgi(&["render", "--incremental", "-1"]), "out of range");
    assert_bad_input(&vkgi(&["render", "--size", "-1x5"]), "at least 1");
    assert_bad_input(&vkgi(&["render", "--frames", "-1"]), "--frames");
}

#[test]
fn an_unknown_device_is_bad_input() {
    assert_bad_input(
        &vkgi(&["render", "--size", "16x12", "--device", "99"]),
        "no device matches",
    );
}

#[test]
fn a_bare_obj_at_1e38_names_the_mesh_not_a_light() {
    let dir = scratch("far-obj");
    let obj = write(
        &dir,
        "far.obj",
        "v 1e38 0 0\nv 1e38 1e37 0\nv 1e38 0 1e37\nf 1 2 3\n",
    );
    assert_bad_input(&render(&obj, &[]), "the mesh reaches coordinate");
}

#[test]
fn a_hundred_point_lights_are_refused_up_front() {
    let lights: String = (0..100)
        .map(|i| {
            format!(
                "[[light]]\ntype = \"point\"\nposition = [{}, 1, 0]\nflux = 1\n",
                i as f32 * 0.01
            )
        })
        .collect();
    let dir = scratch("lights");
    write(&dir, "quad.obj", QUAD);
    write(&dir, "m.mtl", MTL);
    let scene = write(
        &dir,
        "scene.toml",
        &format!(
            "mesh = \"quad.obj\"\n[camera]\nposition = [0, 2, 3]\ntarget = [0, 0, 0]\nfov = 50\n{lights}"
        ),
    );
    assert_bad_input(&render(&scene, &[]), "shadow map of 100 light(s)");
}

#[test]
fn indirect_only_without_a_method_is_refused() {
    assert_bad_input(
        &vkgi(&[
            "render",
            "--size",
            "16x12",
            "--method",
            "none",
            "--indirect-only",
        ]),
        "black image",
    );
}

#[test]
fn a_lattice_beyond_the_device_buffers_is_refused_for_every_blocking_model() {
    for lobe in ["two-sided", "oriented", "visibility"] {
        let lattice = [
            "--method",
            "ilpv",
            "--lattice",
            "512",
            "--blocking-lobe",
            lobe,
        ];
        let args = [&["render", "--size", "16x12"][..], &lattice[..]].concat();
        assert_bad_input(&vkgi(&args), "buffer limit");
    }
}

#[test]
fn profile_with_one_size_says_the_scaling_is_not_fitted() {
    let output = vkgi(&[
        "profile",
        "--method",
        "lpv",
        "--lattice",
        "4",
        "--iterations",
        "1",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "16x12",
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("not fitted") && !stdout.contains("NaN"),
        "{stdout}"
    );
}

#[test]
fn out_naming_a_fifo_or_a_symlink_is_refused_and_left_alone() {
    let dir = scratch("special");
    let target = dir.join("keep.png");
    std::fs::write(&target, b"keep").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    assert_bad_input(
        &vkgi(&[
            "render",
            "--size",
            "16x12",
            "--method",
            "none",
            "--out",
            link.to_str().unwrap(),
        ]),
        "symbolic link",
    );
    assert_eq!(std::fs::read(&target).unwrap(), b"keep");
    let fifo = dir.join("fifo.png");
    if Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        assert_bad_input(
            &vkgi(&[
                "render",
                "--size",
                "16x12",
                "--method",
                "none",
                "--out",
                fifo.to_str().unwrap(),
            ]),
            "not a regular file",
        );
        assert!(!std::fs::symlink_metadata(&fifo).unwrap().is_file());
    }
}

#[test]
fn a_temporary_left_by_a_killed_writer_is_cleaned_on_the_next_write() {
    let dir = scratch("stale");
    let stale = dir.join(".out.png.tmp-2147483632");
    std::fs::write(&stale, vec![0u8; 1024]).unwrap();
    let out = dir.join("out.png");
    let output = vkgi(&[
        "render",
        "--size",
        "16x12",
        "--method",
        "none",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    assert!(out.is_file() && !stale.exists());
}

#[test]
fn malformed_gltf_files_the_gltf_crate_panics_on_are_one_error_line() {
    let dir = scratch("gltf");
    // Each breaks the gltf crate 1.4.1 (a panic inside it) unless vkgi checks it first.
    type Breakage = (&'static str, fn(&mut serde_json::Value), &'static str);
    let breakages: [Breakage; 3] = [
        ("no-accessors", |d| d["accessors"] = json!([]), "POSITION"),
        (
            "no-mime-type",
            |d| {
                d["images"][0].as_object_mut().unwrap().remove("mimeType");
            },
            "mimeType",
        ),
        (
            "view-outside-buffer",
            |d| d["bufferViews"][6]["byteOffset"] = json!(1 << 20),
            "outside buffer",
        ),
    ];
    for (name, break_it, needle) in breakages {
        let (mut document, bin) = gltf_document(true, None);
        break_it(&mut document);
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, glb_bytes(&document, bin)).unwrap();
        assert_bad_input(&render(path.to_str().unwrap(), &[]), needle);
    }
    let truncated = dir.join("truncated.glb");
    let (document, bin) = gltf_document(true, None);
    std::fs::write(&truncated, &glb_bytes(&document, bin)[..100]).unwrap();
    assert_bad_input(&render(truncated.to_str().unwrap(), &[]), "truncated.glb");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unsupported_gltf_features_are_one_warning_each_not_an_error() {
    let dir = scratch("gltf-unsupported");
    let (mut document, bin) = gltf_document(true, None);
    document["skins"] = json!([{"joints": [1]}]);
    document["nodes"][0]["skin"] = json!(0);
    document["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_materials_transmission"]);
    document["materials"][0]["normalTexture"] = json!({"index": 0});
    document["materials"][1]["normalTexture"] = json!({"index": 0});
    let path = dir.join("scene.glb");
    std::fs::write(&path, glb_bytes(&document, bin)).unwrap();
    let output = render(
        path.to_str().unwrap(),
        &["--out", dir.join("o.png").to_str().unwrap()],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    for needle in ["KHR_materials_transmission", "normal", "skin"] {
        let count = warnings.iter().filter(|l| l.contains(needle)).count();
        assert_eq!(count, 1, "one warning about {needle}: {stderr}");
    }
    assert_eq!(warnings.len(), 3, "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}
