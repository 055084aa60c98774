//! The command line on bad input: one clear line on stderr, exit code 2, no panic, nothing
//! half-written. And on good input: files written whole, the profile printed.

use std::path::PathBuf;
use std::process::Output;

mod common;

use common::cli::{assert_bad_input, vkgi, write};

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    common::cli::scratch("cli", name)
}

fn render_scene(scene: &str) -> Output {
    vkgi(&["render", "--scene", scene, "--size", "32x24"])
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

#[test]
fn missing_files_are_reported() {
    assert_bad_input(&render_scene("/nonexistent/mesh.obj"), "no such file");
    assert_bad_input(
        &render_scene("/nonexistent/scene.toml"),
        "cannot read scene file",
    );
    assert_bad_input(&render_scene("nonsense"), "unknown scene");
}

#[test]
fn malformed_obj_mtl_and_toml_are_reported() {
    let dir = scratch("malformed");
    assert_bad_input(
        &render_scene(&write(&dir, "a.obj", "v 0 0 zero\nf 1 2 3\n")),
        "malformed OBJ",
    );
    write(&dir, "b.mtl", "newmtl m\nKd 0.5 oops\n");
    let obj = write(
        &dir,
        "b.obj",
        &format!("mtllib b.mtl\nusemtl m\n{TRIANGLE}"),
    );
    assert_bad_input(&render_scene(&obj), "material");
    let missing_mtl = write(
        &dir,
        "c.obj",
        &format!("mtllib missing.mtl\nusemtl m\n{TRIANGLE}"),
    );
    assert_bad_input(&render_scene(&missing_mtl), "material");
    let toml = write(
        &dir,
        "d.toml",
        "mesh = \"b.obj\"\n[camera\nposition = [0, 0, 1]\n",
    );
    assert_bad_input(&render_scene(&toml), "malformed scene file");
    let bad_value = write(&dir, "e.toml", "mesh = \"b.obj\"\nscale = \"big\"\n");
    assert_bad_input(&render_scene(&bad_value), "malformed scene file");
}

#[test]
fn non_finite_and_empty_meshes_are_reported() {
    let dir = scratch("geometry");
    assert_bad_input(
        &render_scene(&write(
            &dir,
            "nan.obj",
            "v 0 0 0\nv NaN 0 0\nv 0 1 0\nf 1 2 3\n",
        )),
        "non-finite",
    );
    assert_bad_input(
        &render_scene(&write(
            &dir,
            "inf.obj",
            "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n",
        )),
        "non-finite",
    );
    assert_bad_input(
        &render_scene(&write(&dir, "empty.obj", "# no faces\nv 0 0 0\n")),
        "empty",
    );
    assert_bad_input(
        &render_scene(&write(
            &dir,
            "flat.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
        )),
        "empty",
    );
}

#[test]
fn zero_area_triangles_are_skipped_with_a_warning() {
    let dir = scratch("degenerate");
    let obj = write(
        &dir,
        "mixed.obj",
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n",
    );
    let out = dir.join("mixed.png");
    let output = vkgi(&[
        "render",
        "--scene",
        &obj,
        "--size",
        "32x24",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("skipped 1 zero-area triangle"), "{stderr}");
    assert!(out.is_file());
}

#[test]
fn a_scene_without_light_is_reported() {
    let dir = scratch("nolight");
    write(&dir, "tri.obj", TRIANGLE);
    let toml = write(&dir, "dark.toml", "mesh = \"tri.obj\"\n");
    assert_bad_input(&render_scene(&toml), "no light");
    let zero_cone = write(
        &dir,
        "cone.toml",
        "mesh = \"tri.obj\"\n[[light]]\ntype = \"spot\"\nposition = [0,0,1]\ndirection = [0,0,-1]\ncone_angle = 0\npenumbra = 0\nflux = 1\n",
    );
    assert_bad_input(&render_scene(&zero_cone), "cone_angle");
    let nan_flux = write(
        &dir,
        "flux.toml",
        "mesh = \"tri.obj\"\n[[light]]\ntype = \"point\"\nposition = [0,0,1]\nflux = nan\n",
    );
    assert_bad_input(&render_scene(&nan_flux), "flux");
}

#[test]
fn absurd_sizes_and_settings_are_reported() {
    assert_bad_input(&vkgi(&["render", "--size", "0x0"]), "out of range");
    assert_bad_input(
        &vkgi(&["render", "--size", "100000x100000"]),
        "out of range",
    );
    assert_bad_input(&vkgi(&["render", "--size", "big"]), "WIDTHxHEIGHT");
    assert_bad_input(
        &vkgi(&["render", "--size", "32x24", "--shadow-map", "0"]),
        "shadow map",
    );
    assert_bad_input(
        &vkgi(&["render", "--size", "32x24", "--frames", "0"]),
        "frames",
    );
    assert_bad_input(&vkgi(&["render", "--no-such-flag"]), "no-such-flag");
    for bounces in ["0", "33", "two"] {
        assert_bad_input(
            &vkgi(&[
                "render",
                "--size",
                "32x24",
                "--method",
                "irradiance-cache",
                "--bounces",
                bounces,
            ]),
            "1 to 32 bounces, or inf",
        );
    }
}

#[test]
fn outputs_are_written_whole_or_not_at_all() {
    let dir = scratch("outputs");
    let png = dir.join("c.png");
    let exr = dir.join("c.exr");
    let json = dir.join("p.json");
    let trace = dir.join("t.json");
    let output = vkgi(&[
        "render",
        "--scene",
        "cornell",
        "--size",
        "48x36",
        "--out",
        png.to_str().unwrap(),
        "--hdr",
        exr.to_str().unwrap(),
        "--profile",
        "--frames",
        "3",
        "--profile-json",
        json.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for pass in [
        "shadow map",
        "g-buffer",
        "direct lighting",
        "tone map",
        "frame",
    ] {
        assert!(
            stdout.contains(pass),
            "profile table lacks '{pass}':\n{stdout}"
        );
    }
    let decoded = image::open(&png).unwrap();
    assert_eq!((decoded.width(), decoded.height()), (48, 36));
    let hdr = vkgi::imageio::read_hdr(&exr, false).unwrap();
    assert_eq!((hdr.width, hdr.height), (48, 36));
    let profile: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(profile["frames"], 3);
    let events: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&trace).unwrap()).unwrap();
    assert!(!events["traceEvents"].as_array().unwrap().is_empty());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    // A folder that does not exist: an error, and no file anywhere.
    let missing = dir.join("no-such-folder").join("c.png");
    assert_bad_input(
        &vkgi(&[
            "render",
            "--size",
            "32x24",
            "--out",
            missing.to_str().unwrap(),
        ]),
        "does not exist",
    );
}

#[test]
fn reference_writes_its_images_and_settings_and_reuses_them() {
    let dir = scratch("reference");
    let out = dir.join("ref.exr");
    let png = dir.join("ref.png");
    let args = [
        "reference",
        "--scene",
        "cornell",
        "--spp",
        "4",
        "--bounces",
        "1",
        "--size",
        "16x12",
        "--split",
        "--out",
        out.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ];
    let first = vkgi(&args);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    for name in [
        "ref.exr",
        "ref.direct.exr",
        "ref.indirect.exr",
        "ref.png",
        "ref.exr.json",
    ] {
        assert!(dir.join(name).is_file(), "{name} missing");
    }
    let sidecar: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("ref.exr.json")).unwrap()).unwrap();
    assert_eq!(sidecar["key"]["settings"]["spp"], 4);
    assert_eq!(sidecar["key"]["settings"]["bounces"], 1);
    assert_eq!(sidecar["split"], true);
    let mut reuse = args.to_vec();
    reuse.push("--reuse");
    let second = vkgi(&reuse);
    assert!(
        String::from_utf8_lossy(&second.stderr).contains("reusing"),
        "{second:?}"
    );
    // The device and the CPU's cores trace the same estimator with the same random numbers.
    let traced = |tracer: &str| {
        let file = dir.join(format!("ref-{tracer}.exr"));
        let mut on = args.to_vec();
        on.truncate(on.len() - 5); // no --split, --out, --png
        on.extend(["--tracer", tracer, "--out", file.to_str().unwrap()]);
        let run = vkgi(&on);
        assert!(run.status.success(), "{run:?}");
        let sidecar: serde_json::Value = serde_json::from_slice(
            &std::fs::read(dir.join(format!("ref-{tracer}.exr.json"))).unwrap(),
        )
        .unwrap();
        let image = vkgi::imageio::read_hdr(&file, false).unwrap();
        (sidecar["device"].as_str().unwrap().to_string(), image)
    };
    let ((on_gpu, gpu_image), (on_cpu, cpu_image)) = (traced("gpu"), traced("cpu"));
    assert!(on_cpu.starts_with("the CPU ("), "{on_cpu}");
    assert!(!on_gpu.starts_with("the CPU"), "{on_gpu}");
    let sum = |i: &vkgi::imageio::HdrImage| {
        i.pixels
            .iter()
            .flatten()
            .map(|&v| f64::from(v))
            .sum::<f64>()
    };
    let (g, c) = (sum(&gpu_image), sum(&cpu_image));
    assert!((g - c).abs() <= 1e-3 * c, "device {g}, CPU {c}");
    // compare: an image against itself scores zero everywhere (and 100% similar).
    let same = vkgi(&["compare", out.to_str().unwrap(), out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&same.stdout);
    assert!(same.status.success());
    for metric in [
        "RMSE 0.000000",
        "relMSE 0.000000",
        "MAE 0.000000",
        "FLIP 0.000000",
        "similarity 100.000%",
    ] {
        assert!(stdout.contains(metric), "{stdout}");
    }
    let direct = dir.join("ref.direct.exr");
    let json = dir.join("m.json");
    let heatmap = dir.join("flip.png");
    let scored = vkgi(&[
        "compare",
        direct.to_str().unwrap(),
        out.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
        "--heatmap",
        heatmap.to_str().unwrap(),
    ]);
    assert!(scored.status.success());
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert!(metrics["rmse"].as_f64().unwrap() > 0.0);
    assert!(heatmap.is_file());
}

#[test]
fn reference_and_compare_reject_bad_input() {
    let dir = scratch("compare");
    let out = dir.join("x.exr");
    let out = out.to_str().unwrap();
    assert_bad_input(
        &vkgi(&["reference", "--bounces", "lots", "--out", out]),
        "bounce",
    );
    assert_bad_input(
        &vkgi(&["reference", "--spp", "0", "--size", "8x8", "--out", out]),
        "spp",
    );
    assert_bad_input(
        &vkgi(&["reference", "--size", "0x0", "--spp", "1", "--out", out]),
        "out of range",
    );
    let a = dir.join("a.exr");
    let b = dir.join("b.exr");
    let nan = dir.join("nan.exr");
    vkgi::imageio::write_exr(&a, &vkgi::imageio::HdrImage::new(2, 2, vec![[1.0; 3]; 4])).unwrap();
    vkgi::imageio::write_exr(&b, &vkgi::imageio::HdrImage::new(3, 2, vec![[1.0; 3]; 6])).unwrap();
    vkgi::imageio::write_exr(
        &nan,
        &vkgi::imageio::HdrImage::new(2, 2, vec![[f32::NAN; 3]; 4]),
    )
    .unwrap();
    let (a, b, nan) = (
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        nan.to_str().unwrap(),
    );
    assert_bad_input(&vkgi(&["compare", a, b]), "sizes differ");
    assert_bad_input(&vkgi(&["compare", nan, a]), "non-finite");
    assert_bad_input(&vkgi(&["compare", a, "/nonexistent.exr"]), "no such file");
    let garbage = write(&dir, "garbage.exr", "not an image");
    assert_bad_input(&vkgi(&["compare", &garbage, a]), "cannot read image");
    assert_bad_input(
        &vkgi(&["compare", a, a, "--mask", "/nonexistent.png"]),
        "no such file",
    );
}

#[test]
fn a_dynamic_scene_renders_its_last_frame_and_the_reference_poses_any_frame() {
    let dir = scratch("dynamic");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    // cornell-moving's tall block is furthest along its path at frame 60.
    let render = vkgi(&[
        "render",
        "--scene",
        "cornell-moving",
        "--method",
        "none",
        "--frames",
        "61",
        "--size",
        "48x36",
        "--hdr",
        &path("render.exr"),
    ]);
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
    let reference = |frame: &str, out: &str| {
        let run = vkgi(&[
            "reference",
            "--scene",
            "cornell-moving",
            "--bounces",
            "0",
            "--spp",
            "64",
            "--size",
            "48x36",
            "--frame",
            frame,
            "--out",
            &path(out),
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        vkgi::imageio::read_hdr(&dir.join(out), false).unwrap()
    };
    let rendered = vkgi::imageio::read_hdr(&dir.join("render.exr"), false).unwrap();
    let error = |frame: &str| {
        let reference = reference(frame, &format!("frame-{frame}.exr"));
        vkgi::metrics::compare(&rendered, &reference, None)
            .unwrap()
            .rel_mse
    };
    let (at_60, at_0) = (error("60"), error("0"));
    eprintln!(
        "direct light of render --frames 61 against the path tracer's frame 60: relMSE {at_60:.4}, frame 0: {at_0:.4}"
    );
    assert!(at_60 < 0.25 * at_0, "{at_60} against {at_0}");
    assert_bad_input(
        &vkgi(&[
            "reference",
            "--scene",
            "cornell-moving",
            "--frame",
            "-1",
            "--out",
            &path("x.exr"),
        ]),
        "--frame",
    );
}

/// `--lookup-apart` draws LPV's lookup as a pass of its own after direct lighting, where it is
/// otherwise drawn inside direct lighting; the profile table names what ran.
#[test]
fn lookup_apart_times_the_lookup_on_its_own() {
    for (extra, ran, not_ran) in [
        (None, "direct lighting + lpv lookup", "lpv lookup "),
        (
            Some("--lookup-apart"),
            "lpv lookup ",
            "direct lighting + lpv lookup",
        ),
    ] {
        let mut args = vec![
            "render",
            "--scene",
            "cornell",
            "--method",
            "lpv",
            "--size",
            "32x24",
            "--profile",
        ];
        args.extend(extra);
        let output = vkgi(&args);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        let row = |pass: &str| stdout.lines().any(|line| line.starts_with(pass));
        assert!(row(ran), "{extra:?}: no '{ran}' in\n{stdout}");
        assert!(!row(not_ran), "{extra:?}: '{not_ran}' in\n{stdout}");
    }
}
