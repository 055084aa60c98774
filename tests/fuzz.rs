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

use common::fuzzing::{EXTREMES, Rng, Tally, env_number, outcome, quietly};
use vkgi::gi::registry::{self, Setup};
use vkgi::render::runner::run_frames;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;
use vkgi::scene::file::load_embedded;

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

/// What loading one case gave: Ok (with a broken invariant, if any) or an error line.
fn load(texts: &[String; 3]) -> Result<Result<Scene, String>, String> {
    let [toml, obj, mtl] = texts;
    outcome(std::panic::catch_unwind(|| {
        load_embedded("fuzz", toml, obj, mtl)
    }))
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
    let mut tally = Tally::default();
    quietly(|| {
        for n in 0..cases {
            let texts = case(seed, n);
            if let Some(dir) = &corpus {
                write_corpus(dir, n, &texts);
            }
            tally.record(n, load(&texts));
        }
    });
    tally.assert_clean("fuzz", cases, seed, "VKGI_FUZZ_SEED");
}

#[test]
fn loadable_mutated_scenes_render_finite_with_every_method() {
    let seed = env_number("VKGI_FUZZ_SEED", 0x5EED_F022) ^ 0xFACE;
    let wanted = env_number("VKGI_FUZZ_RENDERS", 8);
    let gpu = common::gpu();
    let scenes = quietly(|| {
        let mut scenes = Vec::new();
        let mut n = 0;
        while (scenes.len() as u64) < wanted && n < 100 * wanted {
            if let Ok(Ok(scene)) = load(&case(seed, n)) {
                scenes.push((n, scene));
            }
            n += 1;
        }
        scenes
    });
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
