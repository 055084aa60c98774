//! The windowed renderer under Xvfb (each test starts its own virtual display with xvfb-run,
//! one at a time), and the CAVE's shared lattice and seams on the headless frame.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Mutex;

use glam::Vec3;
use vkgi::gi::lpv::{Lpv, LpvSettings};
use vkgi::gi::registry::Setup;
use vkgi::gpu::frames::FrameRing;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;
use vkgi::view::cave::Cave;

mod common;

/// xvfb-run -a picks a display number racily; windows open one test at a time.
static DISPLAY: Mutex<()> = Mutex::new(());

/// Run `vkgi` with a virtual X display, validation on.
fn vkgi_windowed(args: &[&str]) -> Output {
    vkgi_windowed_in(&std::env::temp_dir(), args)
}

/// As [`vkgi_windowed`], in the working directory `dir`.
fn vkgi_windowed_in(dir: &Path, args: &[&str]) -> Output {
    let _one_at_a_time = DISPLAY.lock().unwrap_or_else(|e| e.into_inner());
    Command::new("xvfb-run")
        .current_dir(dir)
        .args([
            "-a",
            "-s",
            "-screen 0 1024x768x24",
            env!("CARGO_BIN_EXE_vkgi"),
        ])
        .args(args)
        .env("VKGI_VALIDATE", "1")
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("xvfb-run runs (Debian package xvfb)")
}

fn vkgi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(args)
        .env("VKGI_VALIDATE", "1")
        .output()
        .expect("the vkgi binary runs")
}

fn assert_success(output: &Output) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "vkgi failed: {stderr}");
    assert!(
        !stderr.contains("validation:"),
        "validation messages: {stderr}"
    );
}

/// How many frames of a profile report (`--profile-json`) ran the pass called `name`.
fn pass_runs(report: &serde_json::Value, name: &str) -> usize {
    report["passes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == name)
        .map_or(0, |p| p["per_frame_ns"].as_array().unwrap().len())
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-view-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn rgba(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

#[test]
fn the_window_renders_30_frames_and_its_screenshot_equals_the_headless_render() {
    let dir = scratch("match");
    let shot = dir.join("shot");
    let common = [
        "--scene", "cornell", "--size", "160x120", "--method", "ilpv",
    ];
    let mut view = vec![
        "view",
        "--frames",
        "30",
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    view.extend(common);
    assert_success(&vkgi_windowed(&view));
    let headless = dir.join("headless.png");
    let mut render = vec![
        "render",
        "--frames",
        "30",
        "--out",
        headless.to_str().unwrap(),
    ];
    render.extend(common);
    assert_success(&vkgi(&render));

    let (window, headless) = (rgba(&dir.join("shot.png")), rgba(&headless));
    assert_eq!(window.dimensions(), (160, 120));
    let differences: Vec<i32> = window
        .pixels()
        .zip(headless.pixels())
        .flat_map(|(a, b)| (0..3).map(move |c| (i32::from(a[c]) - i32::from(b[c])).abs()))
        .collect();
    let worst = differences.iter().copied().max().unwrap();
    let mean = differences.iter().sum::<i32>() as f64 / differences.len() as f64;
    assert!(
        worst <= 2 && mean < 0.05,
        "worst {worst}/255, mean {mean}/255"
    );
    let brightness = headless.pixels().map(|p| u64::from(p[1])).sum::<u64>();
    assert!(brightness > 0, "the image is not black");

    // The window image is the view plus the overlay: same size, and the overlay darkened or
    // wrote text into its top-left corner.
    let composed = rgba(&dir.join("shot-window.png"));
    assert_eq!(composed.dimensions(), (160, 120));
    let overlay_changed = (8..40)
        .flat_map(|y| (8..150).map(move |x| (x, y)))
        .filter(|&(x, y)| composed.get_pixel(x, y) != window.get_pixel(x, y))
        .count();
    assert!(overlay_changed > 500, "overlay pixels: {overlay_changed}");
    assert!(dir.join("shot.exr").exists());
}

#[test]
fn resizing_the_window_rebuilds_the_swapchain_and_views_without_validation_errors() {
    let dir = scratch("resize");
    let shot = dir.join("shot");
    assert_success(&vkgi_windowed(&[
        "view",
        "--size",
        "160x120",
        "--frames",
        "12",
        "--resize-to",
        "200x150",
        "--screenshot",
        shot.to_str().unwrap(),
    ]));
    assert_eq!(rgba(&dir.join("shot-window.png")).dimensions(), (200, 150));
    assert_eq!(rgba(&dir.join("shot.png")).dimensions(), (200, 150));
}

#[test]
fn the_cave_opens_tiled_and_in_one_window_per_wall() {
    let dir = scratch("cave");
    let shot = dir.join("tiled");
    assert_success(&vkgi_windowed(&[
        "view",
        "--cave",
        "--size",
        "240x160",
        "--frames",
        "4",
        "--screenshot",
        shot.to_str().unwrap(),
    ]));
    assert_eq!(rgba(&dir.join("tiled.png")).dimensions(), (80, 80));
    assert_success(&vkgi_windowed(&[
        "view",
        "--cave",
        "--cave-windows",
        "--size",
        "96x96",
        "--frames",
        "3",
    ]));
}

/// Run the viewer in `dir` for `frames` frames pressing `keys` (one per frame), with `extra`
/// arguments; its profile report.
fn view_with_keys(dir: &Path, extra: &[&str], frames: u32, keys: &str) -> serde_json::Value {
    let profile = dir.join("profile.json");
    let frames = frames.to_string();
    let mut args = vec![
        "view",
        "--frames",
        &frames,
        "--keys",
        keys,
        "--profile-json",
    ];
    args.push(profile.to_str().unwrap());
    args.extend_from_slice(extra);
    assert_success(&vkgi_windowed_in(dir, &args));
    serde_json::from_str(&std::fs::read_to_string(&profile).unwrap()).unwrap()
}

#[test]
fn keys_switch_method_and_settings_move_the_light_and_save_screenshots() {
    let dir = scratch("keys");
    // Per frame (the method cycle is none, then the registry's order: ambient, ilpv, lightwave,
    // lpv, radiosity, irradiance-cache, radiance-volumes; the default is ilpv): lightwave, lpv,
    // radiosity, irradiance-cache, radiance-volumes, none, ambient, ilpv, lattice +2, steps +1,
    // λ +0.05, light right, indirect only, direct only, screenshot, help.
    let report = view_with_keys(
        &dir,
        &["--size", "96x72"],
        16,
        "m,m,m,m,m,m,m,m,],.,=,right,i,o,p,f1",
    );
    for file in [
        "vkgi-screenshot-1.png",
        "vkgi-screenshot-1.exr",
        "vkgi-screenshot-1-window.png",
    ] {
        assert!(dir.join(file).exists(), "{file} was saved");
    }
    assert_eq!(report["frames"], 16);
    let runs = |name: &str| pass_runs(&report, name);
    // Injection runs with lpv in frame 1 and ilpv in frames 7-12: not with lightwave (frame 0),
    // radiosity (frame 2), irradiance-cache (frame 3), radiance-volumes (frame 4), none (frame
    // 5) or ambient (frame 6), nor once "o" (direct only) is on. ILPV injects anew in the
    // frames it is built (7-10: the method, the lattice, the steps, λ) and where the light moved
    // (11); in frame 12 ("i": indirect only) nothing it depends on changed and it copies the
    // injection it kept.
    assert_eq!(runs("inject"), 6);
    assert_eq!(runs("kept injection"), 1);
    // Ambient's term and radiosity's display are drawn inside direct lighting (lavapipe runs
    // it as a fragment pass).
    assert_eq!(runs("direct lighting + ambient"), 1);
    assert_eq!(runs("lightwave gather"), 1);
    assert_eq!(runs("direct lighting + radiosity display"), 1);
    assert_eq!(runs("ic normalise"), 1);
    assert_eq!(runs("rv apply"), 1);
    assert_eq!(runs("g-buffer"), 16);
    assert_eq!(runs("update lights"), 1, "the light moved once");
}

#[test]
fn keys_dim_tint_and_aim_the_light_and_only_move_an_emitter() {
    let dir = scratch("light-keys");
    // Per frame on the Cornell box's spot: dim, brighten, tint, turn, tilt, and one frame with
    // no key: five light updates.
    let report = view_with_keys(&dir, &["--size", "32x24"], 6, "j,k,t,z,r,f1");
    assert_eq!(pass_runs(&report, "update lights"), 5);
    // cornell-area has only its ceiling emitter: J, K and T change nothing (one line says so).
    let dir = scratch("emitter-keys");
    let report = view_with_keys(
        &dir,
        &["--scene", "cornell-area", "--size", "32x24"],
        3,
        "j,t,z",
    );
    assert_eq!(pass_runs(&report, "update lights"), 0);
}

#[test]
fn lightwave_keys_switch_its_gather_shells_shadows_and_composite() {
    let dir = scratch("lightwave-keys");
    // Per frame: gather per pixel, per vertex again, a sixth shell, integrated shadows, the
    // composite back from eq4.9 to fake (choices cycle), which gathers nothing.
    let report = view_with_keys(
        &dir,
        &["--method", "lightwave", "--size", "32x24"],
        5,
        "h,h,],;,c",
    );
    let runs = |name: &str| pass_runs(&report, name);
    assert_eq!(runs("lightwave gather"), 5);
    assert_eq!(
        runs("lightwave vertex gather"),
        3,
        "not in the per-pixel frame nor with the fake composite"
    );
    assert_eq!(runs("lightwave triangle ids"), 3);
    assert_eq!(runs("lightwave vpls"), 5);
}

#[test]
fn the_arrow_keys_move_an_emitter_and_the_method_is_rebuilt_when_they_let_go() {
    let dir = scratch("emitter");
    // cornell-area has no punctual light: the arrows move its ceiling light. Per frame (with
    // ilpv, the default method): the emitter right twice, then two frames without arrows (ilpv
    // is made again around the moved emitter in the first of them).
    let report = view_with_keys(
        &dir,
        &["--scene", "cornell-area", "--size", "64x48"],
        4,
        "right,right,f1,f1",
    );
    let runs = |name: &str| pass_runs(&report, name);
    assert_eq!(runs("update vertices"), 2, "the emitter moved twice");
    assert_eq!(runs("update lights"), 2, "its light samples followed");
    let notes = report["notes"].as_array().unwrap();
    assert!(
        notes
            .iter()
            .any(|n| n == "frame 2: ilpv made again around the moved emitter"),
        "{notes:?}"
    );
}

#[test]
fn dynamic_objects_follow_their_paths_and_the_arrow_keys_and_methods_follow_them() {
    // cornell-moving's block moves every frame of its path: frames 1-4 write its vertices, and
    // ILPV's two lattices write their rebuilt cells in the same frames.
    let dir = scratch("dynamic-path");
    let report = view_with_keys(
        &dir,
        &["--scene", "cornell-moving", "--size", "32x24"],
        5,
        "f1",
    );
    assert_eq!(pass_runs(&report, "update vertices"), 4);
    assert_eq!(pass_runs(&report, "update geometry lattice"), 4);
    // Radiosity cannot follow: it is made again for every frame the block moved.
    let dir = scratch("dynamic-radiosity");
    let args = [
        "--scene",
        "cornell-moving",
        "--size",
        "32x24",
        "--method",
        "radiosity",
    ];
    let report = view_with_keys(&dir, &args, 3, "f1");
    assert_eq!(pass_runs(&report, "update vertices"), 2);
    // A box that stays put unless the arrows move it: L chooses it (after the scene's light),
    // two frames of the right arrow move it.
    let dir = scratch("dynamic-keys");
    let scene = dir.join("still.toml");
    let cornell = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cornell-box.obj");
    std::fs::write(
        &scene,
        format!(
            "mesh = {:?}\nscale = 0.001\n[[light]]\ntype = \"point\"\nposition = [278, 400, 280]\nflux = 3\n[[dynamic]]\nbox = [[100, 200, 100], [200, 300, 200]]\npath = [{{ frame = 0, offset = [0, 0, 0] }}]\n",
            cornell.to_str().unwrap()
        ),
    )
    .unwrap();
    let args = ["--scene", scene.to_str().unwrap(), "--size", "32x24"];
    let report = view_with_keys(&dir, &args, 4, "l,right,right,f1");
    assert_eq!(pass_runs(&report, "update vertices"), 2);
}

#[test]
fn radiosity_id_and_pd_follow_the_camera_and_the_mode_keys() {
    let dir = scratch("radiosity-modes");
    // pd: the camera's importance and the simulated view are marked on frame 1 and again when
    // W moves the camera (frame 2); "]" cycles pd to pr (frame 4), which has no camera pass, so
    // moving on frame 5 marks nothing.
    let report = view_with_keys(
        &dir,
        &[
            "--scene",
            "cornell-area",
            "--size",
            "48x36",
            "--method",
            "radiosity",
            "--radiosity-mode",
            "pd",
        ],
        5,
        "f1,w,f1,],w",
    );
    let runs = |name: &str| pass_runs(&report, name);
    // Frames a pass ran in: the camera passes on frames 1 and 2 only, pd's table on 1 to 3.
    assert_eq!(runs("radiosity view"), 2);
    assert_eq!(runs("radiosity table store"), 3);
    assert_eq!(runs("radiosity stats"), 5, "pr shoots on after the switch");
}

#[test]
fn view_rejects_bad_input_and_a_missing_display_with_one_line() {
    let output = vkgi(&["view", "--size", "0x0"]);
    assert_eq!(output.status.code(), Some(2));
    let output = Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("needs a display"), "{stderr}");
}

/// The CAVE's four walls from its centre, rendered headless: indirect light of each wall.
fn cave_frame(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    side: u32,
) -> (Frame, Lpv, FrameRing, Vec<Vec<[f32; 3]>>) {
    let cave = Cave::placed(scene, 0.2, Vec3::new(0.2, 0.1, 0.3));
    let options = FrameOptions {
        indirect_only: true,
        ..common::indirect_only(side, side)
    };
    let mut frame = Frame::with_eyes(gpu, scene, options, &cave.eyes(scene)).expect("frame");
    let mut lpv = Lpv::new(&Setup::new(gpu, scene), LpvSettings::default()).expect("lpv");
    let mut ring = FrameRing::new(gpu, 2).expect("ring");
    for _ in 0..12 {
        frame.submit(gpu, &mut ring, Some(&mut lpv)).expect("frame");
    }
    ring.finish().expect("finish");
    let walls = (0..4)
        .map(|v| frame.read_view_hdr(gpu, v).expect("readback"))
        .collect();
    (frame, lpv, ring, walls)
}

#[test]
fn cave_walls_agree_along_their_shared_edges() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let n = 64usize;
    let (_, _, _, walls) = cave_frame(&gpu, &scene, n as u32);
    let [front, left, right, floor] = [&walls[0], &walls[1], &walls[2], &walls[3]];
    let at = |wall: &Vec<[f32; 3]>, x: usize, y: usize| common::luminance(wall[y * n + x]);
    // Relative difference of two pixel runs, over the run's mean.
    let difference = |pairs: Vec<(f32, f32)>| {
        let diff: f32 = pairs.iter().map(|(a, b)| (a - b).abs()).sum();
        let mean: f32 = pairs.iter().map(|(a, b)| 0.5 * (a + b)).sum();
        assert!(mean > 0.0, "the seam is lit");
        diff / mean
    };
    let seams = [
        (
            "front|right",
            difference(
                (0..n)
                    .map(|y| (at(front, n - 1, y), at(right, 0, y)))
                    .collect(),
            ),
        ),
        (
            "left|front",
            difference(
                (0..n)
                    .map(|y| (at(left, n - 1, y), at(front, 0, y)))
                    .collect(),
            ),
        ),
        (
            "front/floor",
            difference(
                (0..n)
                    .map(|x| (at(front, x, n - 1), at(floor, x, 0)))
                    .collect(),
            ),
        ),
    ];
    // Control: edges that do not meet (the front wall's left and right edges).
    let apart = difference(
        (0..n)
            .map(|y| (at(front, 0, y), at(front, n - 1, y)))
            .collect(),
    );
    println!("seam differences {seams:?}, edges apart {apart}");
    for (name, seam) in seams {
        assert!(
            seam < 0.1 && seam < 0.5 * apart,
            "{name}: {seam} (edges apart: {apart})"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_gi_light_is_computed_once_per_frame_however_many_views() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (_, _, cave_ring, _) = cave_frame(&gpu, &scene, 32);
    let count = |ring: &FrameRing, prefix: &str| {
        let samples = ring.profiler.samples();
        let frames = samples
            .iter()
            .map(|s| s.frame)
            .collect::<std::collections::HashSet<_>>();
        let runs = samples
            .iter()
            .filter(|s| s.name.starts_with(prefix))
            .count();
        runs as f64 / frames.len() as f64
    };
    let mut single_ring = FrameRing::new(&gpu, 2).unwrap();
    let mut frame = Frame::new(&gpu, &scene, common::indirect_only(32, 32)).unwrap();
    let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), LpvSettings::default()).unwrap();
    for _ in 0..12 {
        frame
            .submit(&gpu, &mut single_ring, Some(&mut lpv))
            .unwrap();
    }
    single_ring.finish().unwrap();
    for pass in ["propagate", "inject", "rsm"] {
        let (one, four) = (count(&single_ring, pass), count(&cave_ring, pass));
        assert!(one > 0.0, "{pass} runs");
        assert_eq!(one, four, "{pass} per frame: 1 view {one}, 4 views {four}");
    }
    assert_eq!(count(&single_ring, "g-buffer"), 1.0);
    assert_eq!(count(&cave_ring, "g-buffer"), 4.0);
    assert_eq!(count(&cave_ring, "direct lighting + lpv lookup"), 4.0);
    common::assert_no_validation_errors(&gpu);
}

/// The irradiance cache's record count and uncovered tiles from the status line in a viewer
/// profile's notes ("records N (+k last round), holes H...").
fn cache_status(report: &serde_json::Value) -> (u64, u64) {
    let notes = report["notes"].as_array().expect("notes");
    let status = notes
        .iter()
        .filter_map(|n| n.as_str())
        .find(|n| n.starts_with("records "))
        .expect("the cache's status line");
    let number_after = |word: &str| -> u64 {
        let rest = &status[status.find(word).expect(word) + word.len()..];
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().expect("a count")
    };
    (number_after("records "), number_after("holes "))
}

#[test]
fn irradiance_cache_records_refine_as_the_camera_moves() {
    let extra = [
        "--size",
        "96x72",
        "--method",
        "irradiance-cache",
        "--hemisphere-size",
        "16",
    ];
    let still = vec!["f5"; 30].join(",");
    let moving = [vec!["f5"; 10], vec!["w"; 6], vec!["d"; 4], vec!["f5"; 10]].concat();
    let dir = scratch("ic-still");
    let (still_count, still_holes) = cache_status(&view_with_keys(&dir, &extra, 30, &still));
    let dir = scratch("ic-moving");
    let (moved_count, moved_holes) =
        cache_status(&view_with_keys(&dir, &extra, 30, &moving.join(",")));
    assert_eq!(still_holes, 0, "the still view is covered");
    assert_eq!(moved_holes, 0, "the moved view is covered again");
    assert!(
        moved_count > still_count,
        "moving placed records where the view newly needs them: {moved_count} after moving, {still_count} standing still"
    );
}

/// The radiance volumes' counts from their profile note ("radiance volumes: N caches held in
/// the frame before the last, R refused (...), M corners missing, B pixels beyond ...").
fn volume_counts(report: &serde_json::Value) -> (u64, u64, u64) {
    let notes = report["notes"].as_array().expect("notes");
    let line = notes
        .iter()
        .filter_map(|n| n.as_str())
        .find(|n| n.contains("caches held"))
        .expect("the volumes' count line");
    let number_before = |word: &str| -> u64 {
        let head = &line[..line.find(word).expect(word)];
        let digits: String = head
            .trim_end()
            .chars()
            .rev()
            .take_while(char::is_ascii_digit)
            .collect();
        digits
            .chars()
            .rev()
            .collect::<String>()
            .parse()
            .expect("a count")
    };
    (
        number_before("caches held"),
        number_before("corners missing"),
        number_before("refused"),
    )
}

#[test]
fn radiance_volume_caches_are_reallocated_every_frame_as_the_camera_and_light_move() {
    let extra = ["--size", "96x72", "--method", "radiance-volumes"];
    let still = vec!["f5"; 24].join(",");
    let moving = [vec!["w"; 10], vec!["right"; 4], vec!["a"; 4], vec!["f5"; 6]].concat();
    let dir = scratch("rv-still");
    let (still_caches, still_missing, still_refused) =
        volume_counts(&view_with_keys(&dir, &extra, 24, &still));
    let dir = scratch("rv-moving");
    let (moved_caches, moved_missing, moved_refused) =
        volume_counts(&view_with_keys(&dir, &extra, 24, &moving.join(",")));
    println!("caches: {still_caches} standing, {moved_caches} after moving");
    assert!(still_caches > 0, "the still view holds caches");
    assert_eq!((still_missing, still_refused), (0, 0));
    assert_eq!(
        (moved_missing, moved_refused),
        (0, 0),
        "every corner the moved view needs was allocated in its own frame"
    );
    assert_ne!(
        moved_caches, still_caches,
        "the caches were reallocated for the moved view"
    );
}
