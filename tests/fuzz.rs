//! A fuzzing pass kept in the suite (stable Rust: a seeded mutator, no cargo-fuzz). Each case
//! mutates the built-in scenes' scene file (TOML), OBJ and MTL — truncation, random bytes,
//! extreme and non-finite numbers, wrong types, out-of-range indices, short colour lines,
//! missing materials, deleted and duplicated lines — and loads it. A case passes when the loader
//! neither panics (nor reports a caught library panic) and either returns a scene that keeps
//! every invariant the renderer relies on, or one error line. A smaller set of loadable cases is
//! rendered at 32x24 with every registered method, and every pixel must be finite.
//!
//! `VKGI_FUZZ_CASES=N` runs N load cases (default 10 000, under a minute) and
//! `VKGI_FUZZ_RENDERS=N` N render cases (default 8); `VKGI_FUZZ_SEED` changes the seed;
//! `VKGI_FUZZ_CORPUS=DIR` also writes every case as DIR/case-N/{scene.toml, mesh.obj,
//! mesh.mtl}, a corpus for the command line (docs/reliability.md).

use std::path::Path;

use glam::Vec3;
use vkgi::gi::registry::{self, Setup};
use vkgi::render::runner::run_frames;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::file::load_embedded;
use vkgi::scene::{LightKind, MAX_COORDINATE, MAX_POWER, Scene};

mod common;

const SCENES: [(&str, &str, &str); 3] = [
    (
        include_str!("../assets/scenes/cornell.toml"),
        include_str!("../assets/cornell-box.obj"),
        include_str!("../assets/cornell-box.mtl"),
    ),
    (
        concat!(
            include_str!("../assets/scenes/cornell.toml"),
            "\n[[light]]\ntype = \"area\"\ncenter = [278, 547, 280]\n",
            "edges = [[130, 0, 0], [0, 0, 105]]\nradiance = 30\ntwo_sided = false\n"
        ),
        include_str!("../assets/cornell-box.obj"),
        include_str!("../assets/cornell-box.mtl"),
    ),
    (
        include_str!("../assets/scenes/two-rooms.toml"),
        include_str!("../assets/two-rooms.obj"),
        include_str!("../assets/two-rooms.mtl"),
    ),
];

/// Numbers that break naive arithmetic.
const EXTREMES: &[&str] = &[
    "1e38",
    "-1e38",
    "3.4e38",
    "1e39",
    "-1e39",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "0",
    "-0",
    "1e-45",
    "-1e-45",
    "1e-30",
    "99999999999",
    "-1",
    "4294967296",
    "2147483648",
    "1e30",
    "0.5",
    "",
    "x",
    "1,",
    "--1",
];

/// Lines a hostile file might hold.
const LINES: &[&str] = &[
    "f 1 2",
    "f 1",
    "f",
    "f 0 0 0",
    "f 999999 1 2",
    "f -1 -2 -3",
    "f -999 1 2",
    "f 1/1/1 2//2 3/3",
    "v 1e38 1e38 1e38",
    "v nan 0 0",
    "v 1 2",
    "v",
    "vn nan nan nan",
    "vn 0 0 0",
    "vt",
    "usemtl missing",
    "usemtl",
    "mtllib nonexistent.mtl",
    "o",
    "g",
    "s off",
    "newmtl",
    "newmtl x",
    "Kd 0.5",
    "Kd",
    "Ka 0 0",
    "Ks 1 1",
    "Ke 1e38 1e38 1e38",
    "Ke -1 0 0",
    "Kd 2 0 0",
    "Kd nan 0 0",
    "Ns",
    "d",
    "illum",
    "map_Kd",
    "[[light]]",
    "type = \"spot\"",
    "type = \"point\"",
    "type = \"area\"",
    "edges = [[1, 0, 0], [0, 0, 1]]",
    "edges = [[1, 0, 0], [2, 0, 0]]",
    "edges = [[1e38, 0, 0], [0, 0, 1e38]]",
    "edges = [[1e-30, 0, 0], [0, 0, 1e-30]]",
    "center = [0, 0, 0]",
    "radiance = 1e38",
    "radiance = -1",
    "two_sided = true",
    "flux = 3e38",
    "flux = -1",
    "flux = nan",
    "color = [1e38, 1, 1]",
    "color = [1, 1]",
    "position = [1, 2, 3, 4]",
    "position = [1e38, 0, 0]",
    "scale = 1e30",
    "scale = 0",
    "scale = -1",
    "direction = [1e38, 0, 0]",
    "direction = [0, 0, 0]",
    "cone_angle = 90",
    "cone_angle = 0",
    "penumbra = 100",
    "fov = 0",
    "fov = 180",
    "mesh = 5",
    "[camera]",
    "up = [0, 0, 0]",
    "target = [278, 273, -800]",
];

/// Values of the wrong type for a TOML key.
const WRONG_TYPES: &[&str] = &["\"text\"", "[1, 2]", "true", "{ a = 1 }", "[]", "1"];

/// splitmix64: a small seeded generator, so every case can be replayed from its number.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// One mutation of `text`.
fn mutate(rng: &mut Rng, text: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        lines.push(String::new());
    }
    let at = rng.below(lines.len());
    match rng.below(9) {
        0 => {
            // Truncate at a character boundary.
            let cut = rng.below(text.len() + 1);
            let cut = (0..=cut)
                .rev()
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(0);
            return text[..cut].to_string();
        }
        1 => {
            // Replace a few characters with random ones (control characters included).
            let mut chars: Vec<char> = text.chars().collect();
            for _ in 0..1 + rng.below(4) {
                if chars.is_empty() {
                    break;
                }
                let i = rng.below(chars.len());
                chars[i] = char::from_u32((rng.next() % 0x250) as u32).unwrap_or('?');
            }
            return chars.into_iter().collect();
        }
        2 | 3 => {
            // An extreme number in place of a numeric token.
            let mut words: Vec<String> = lines[at].split_whitespace().map(str::to_string).collect();
            let numeric: Vec<usize> = (0..words.len())
                .filter(|&i| {
                    words[i]
                        .trim_matches([',', '[', ']'])
                        .parse::<f64>()
                        .is_ok()
                })
                .collect();
            if !numeric.is_empty() {
                let i = numeric[rng.below(numeric.len())];
                let keep_comma = words[i].ends_with(',');
                words[i] = format!(
                    "{}{}",
                    rng.pick(EXTREMES),
                    if keep_comma { "," } else { "" }
                );
                lines[at] = words.join(" ");
            }
        }
        4 => {
            // Drop a token.
            let mut words: Vec<&str> = lines[at].split_whitespace().collect();
            if !words.is_empty() {
                words.remove(rng.below(words.len()));
            }
            lines[at] = words.join(" ");
        }
        5 => {
            let line = rng.pick(LINES).to_string();
            lines.insert(at, line);
        }
        6 => {
            if let Some((key, _)) = lines[at].split_once('=') {
                lines[at] = format!("{key}= {}", rng.pick(WRONG_TYPES));
            }
        }
        7 => {
            let line = lines[at].clone();
            lines.insert(at, line);
        }
        _ => {
            lines.remove(at);
        }
    }
    lines.join("\n")
}

/// Case `n`: a scene file, OBJ and MTL with 1 to 3 mutations.
fn case(seed: u64, n: u64) -> [String; 3] {
    let mut rng = Rng(seed ^ n.wrapping_mul(0xD6E8_FEB8_6659_FD93));
    let (toml, obj, mtl) = SCENES[rng.below(SCENES.len())];
    let mut texts = [toml.to_string(), obj.to_string(), mtl.to_string()];
    for _ in 0..1 + rng.below(3) {
        let which = rng.below(3);
        texts[which] = mutate(&mut rng, &texts[which]);
    }
    texts
}

/// Why a loaded scene breaks an invariant the renderer relies on, if it does.
fn broken_invariant(scene: &Scene) -> Option<String> {
    let within = |v: Vec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
    if scene.mesh.triangle_count() == 0 {
        return Some("no triangles".into());
    }
    if !scene.mesh.positions.iter().all(|&p| within(p)) {
        return Some("a vertex out of range".into());
    }
    if !scene
        .mesh
        .normals
        .iter()
        .all(|n| *n == Vec3::ZERO || (n.is_finite() && (n.length() - 1.0).abs() < 1e-3))
    {
        return Some("a normal neither unit nor zero".into());
    }
    let vertices = scene.mesh.positions.len();
    if scene
        .mesh
        .indices
        .iter()
        .flatten()
        .any(|&i| i as usize >= vertices)
    {
        return Some("a triangle's vertex index out of range".into());
    }
    if (0..scene.mesh.triangle_count()).any(|t| scene.mesh.face_normal(t) == Vec3::ZERO) {
        return Some("a degenerate triangle".into());
    }
    if scene
        .mesh
        .materials
        .iter()
        .any(|&m| m as usize >= scene.materials.len())
    {
        return Some("a triangle's material out of range".into());
    }
    for m in &scene.materials {
        if !(m.albedo.is_finite() && m.albedo.min_element() >= 0.0 && m.albedo.max_element() <= 1.0)
        {
            return Some(format!("albedo {}", m.albedo));
        }
        if !(m.emission.is_finite() && m.emission.max_element() <= MAX_POWER) {
            return Some(format!("emission {}", m.emission));
        }
    }
    for light in &scene.lights {
        if !within(light.position) {
            return Some(format!("light position {}", light.position));
        }
        let power = light.color * light.flux;
        let intensity = light.intensity();
        if !(power.is_finite() && intensity.is_finite() && power.max_element() <= MAX_POWER) {
            return Some(format!("light power {power}"));
        }
        if let LightKind::Spot { direction, .. } = light.kind
            && (direction.length() - 1.0).abs() > 1e-3
        {
            return Some(format!("spot direction {direction}"));
        }
    }
    let aspect = [0.75f32, 1.0, 4.0 / 3.0];
    if !aspect.iter().all(|&a| {
        scene
            .camera
            .view_projection(a, scene.bounds_min, scene.bounds_max)
            .is_finite()
    }) {
        return Some("a non-finite camera projection".into());
    }
    None
}

/// What loading one case gave: Ok (with a broken invariant, if any) or an error line.
fn load(texts: &[String; 3]) -> Result<Result<Scene, String>, String> {
    let [toml, obj, mtl] = texts;
    let loaded = std::panic::catch_unwind(|| load_embedded("fuzz", toml, obj, mtl));
    match loaded {
        Err(payload) => Err(format!(
            "panic: {}",
            vkgi::error::panic_message(payload.as_ref())
        )),
        Ok(Err(e)) if e.0.contains("failed on this input") => Err(format!("caught panic: {e}")),
        Ok(Err(e)) if e.0.is_empty() || e.0.contains('\n') => {
            Err(format!("not one error line: {:?}", e.0))
        }
        Ok(Err(e)) => Ok(Err(e.0)),
        Ok(Ok(scene)) => match broken_invariant(&scene) {
            Some(why) => Err(format!("loaded, but {why}")),
            None => Ok(Ok(scene)),
        },
    }
}

fn write_corpus(dir: &Path, n: u64, texts: &[String; 3]) {
    let case = dir.join(format!("case-{n}"));
    std::fs::create_dir_all(&case).expect("corpus folder");
    let toml = texts[0]
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("mesh") {
                "mesh = \"mesh.obj\"".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let obj = texts[1]
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("mtllib") {
                "mtllib mesh.mtl".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(case.join("scene.toml"), toml).expect("write");
    std::fs::write(case.join("mesh.obj"), obj).expect("write");
    std::fs::write(case.join("mesh.mtl"), &texts[2]).expect("write");
}

#[test]
fn mutated_scene_files_load_or_fail_with_one_line_never_panic() {
    let seed = env_number("VKGI_FUZZ_SEED", 0x5EED_F022);
    let cases = env_number("VKGI_FUZZ_CASES", 10_000);
    let corpus = std::env::var_os("VKGI_FUZZ_CORPUS").map(std::path::PathBuf::from);
    // Panics inside the loader are what this test looks for: keep their messages off stderr.
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let (mut loaded, mut refused, mut failures) = (0u64, 0u64, Vec::new());
    for n in 0..cases {
        let texts = case(seed, n);
        if let Some(dir) = &corpus {
            write_corpus(dir, n, &texts);
        }
        match load(&texts) {
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(_)) => refused += 1,
            Err(why) => failures.push(format!("case {n}: {why}")),
        }
    }
    std::panic::set_hook(previous_hook);
    eprintln!(
        "fuzz: {cases} cases (seed {seed:#x}): {loaded} loaded and valid, {refused} refused with one line, {} failures",
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {cases} cases failed (replay with VKGI_FUZZ_SEED={seed}):\n{}",
        failures.len(),
        failures
            .iter()
            .take(20)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(
        loaded > 0 && refused > 0,
        "the mutations exercise both outcomes"
    );
}

#[test]
fn loadable_mutated_scenes_render_finite_with_every_method() {
    let seed = env_number("VKGI_FUZZ_SEED", 0x5EED_F022) ^ 0xFACE;
    let wanted = env_number("VKGI_FUZZ_RENDERS", 8);
    let gpu = common::gpu();
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut scenes = Vec::new();
    let mut n = 0;
    while (scenes.len() as u64) < wanted && n < 100 * wanted {
        if let Ok(Ok(scene)) = load(&case(seed, n)) {
            scenes.push((n, scene));
        }
        n += 1;
    }
    std::panic::set_hook(previous_hook);
    assert_eq!(scenes.len() as u64, wanted, "enough loadable cases");
    let options = FrameOptions {
        width: 32,
        height: 24,
        shadow_map_size: 128,
        ..FrameOptions::default()
    };
    for (n, scene) in &scenes {
        let mut frame = Frame::new(&gpu, scene, options.clone())
            .unwrap_or_else(|e| panic!("case {n}: frame: {e:#}"));
        run_frames(&gpu, &mut frame, None, 0, 1).expect("direct light");
        let direct = frame.read_hdr(&gpu).expect("readback");
        assert!(
            direct.iter().flatten().all(|v| v.is_finite()),
            "case {n}: non-finite direct light"
        );
        for entry in registry::methods() {
            let settings = entry.settings(&[]).expect("defaults");
            let mut method = match entry.create(&Setup::new(&gpu, scene), &settings) {
                Ok(m) => m,
                Err(e) if vkgi::app::is_input_error(&e) => continue,
                Err(e) => panic!("case {n}: {}: {e:#}", entry.name),
            };
            let frames = (entry.settle_frames)(&settings).min(4);
            run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames).expect("frames");
            let image = frame.read_hdr(&gpu).expect("readback");
            assert!(
                image.iter().flatten().all(|v| v.is_finite()),
                "case {n}: {} gave non-finite pixels",
                entry.name
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}
