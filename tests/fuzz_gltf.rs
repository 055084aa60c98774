//! The fuzzing pass for glTF 2.0 (stable Rust: a seeded mutator). Each case takes the test
//! fixture scene (tests/common/gltf_fixture.rs) as `.gltf` with an external buffer and image, or
//! as `.glb`, and mutates it 1 to 3 times: JSON values replaced by extreme numbers or values of
//! the wrong type, keys deleted, indices pointing past their arrays, node cycles and deep
//! hierarchies, unsupported features and extensions, non-finite and huge floats and
//! out-of-range indices written into the binary buffer, truncated buffers and images, and
//! truncated or byte-flipped files. A case passes when the loader neither panics (nor reports a
//! caught library panic) and either returns a scene that keeps every invariant the renderer
//! relies on (tests/common/fuzzing.rs), or one error line.
//!
//! `VKGI_FUZZ_GLTF_CASES=N` runs N cases (default 5 000, about 3 s); `VKGI_FUZZ_SEED`
//! changes the seed; `VKGI_FUZZ_GLTF_CORPUS=DIR` keeps every case as DIR/case-N/ (a corpus for
//! the command line, docs/reliability.md).

use std::path::Path;

use common::fuzzing::{Rng, Tally, env_number, outcome, quietly};
use common::gltf_fixture::{glb_bytes, gltf_document, texture_png};
use serde_json::{Value, json};
use vkgi::scene::Scene;

mod common;

/// JSON numbers that break naive arithmetic or indexing (JSON has no NaN or infinity: those
/// reach the loader through the binary buffer instead).
const EXTREME_NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    -1.0,
    1.0,
    3.0,
    99.0,
    65535.0,
    4294967295.0,
    4294967296.0,
    1e12,
    1e30,
    1e38,
    -1e38,
    3.5e38,
    1e300,
    1e-45,
    0.5,
];

/// Floats written into the binary buffer.
const EXTREME_FLOATS: &[f32] = &[
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    1e38,
    -1e38,
    f32::MAX,
    0.0,
    1e-45,
];

/// A file as written to disk: the document, its binary buffer, the external image, and
/// damage done to the serialised bytes.
struct Case {
    glb: bool,
    document: Value,
    bin: Vec<u8>,
    image: Vec<u8>,
    truncate_file: Option<usize>,
    flip_bytes: Vec<(usize, u8)>,
}

/// Every JSON pointer to a value in `value` (objects' and arrays' members, recursively).
fn pointers(value: &Value, at: String, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (key, member) in map {
                let path = format!("{at}/{}", key.replace('~', "~0").replace('/', "~1"));
                out.push(path.clone());
                pointers(member, path, out);
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                let path = format!("{at}/{i}");
                out.push(path.clone());
                pointers(item, path, out);
            }
        }
        _ => {}
    }
}

fn random_pointer(rng: &mut Rng, document: &Value) -> Option<String> {
    let mut all = Vec::new();
    pointers(document, String::new(), &mut all);
    (!all.is_empty()).then(|| all.swap_remove(rng.below(all.len())))
}

/// A JSON value of a random type (the wrong one, mostly).
fn wrong_type(rng: &mut Rng) -> Value {
    match rng.below(6) {
        0 => json!("text"),
        1 => json!([1, 2]),
        2 => json!(true),
        3 => json!({"a": 1}),
        4 => Value::Null,
        _ => json!([]),
    }
}

/// Set member `key` of the object at `pointer` to `value`, if an object is there (earlier
/// mutations may have replaced it).
fn set(document: &mut Value, pointer: &str, key: &str, value: Value) {
    if let Some(Value::Object(map)) = document.pointer_mut(pointer) {
        map.insert(key.to_string(), value);
    }
}

/// Unsupported or hostile structure added to the document.
fn add_structure(rng: &mut Rng, document: &mut Value) {
    match rng.below(8) {
        0 => set(document, "", "skins", json!([{"joints": [0]}])),
        1 => {
            let extension = json!(["KHR_materials_transmission"]);
            set(document, "", "extensionsUsed", extension.clone());
            set(document, "", "extensionsRequired", extension);
        }
        2 => set(document, "/nodes/0", "children", json!([0])),
        3 => {
            // A hierarchy deeper than any scene needs: node k's child is node k + 1.
            if let Some(Value::Array(nodes)) = document.pointer_mut("/nodes") {
                let first = nodes.len();
                for k in 0..400 {
                    nodes.push(json!({"children": [first + k + 1]}));
                }
                nodes.push(json!({"mesh": 0}));
                set(document, "/scenes/0", "nodes", json!([first]));
            }
        }
        4 => set(
            document,
            "/meshes/0/primitives/0",
            "mode",
            json!(rng.below(7)),
        ),
        5 => set(document, "/nodes/1", "matrix", json!(vec![0.0; 16])),
        6 => set(document, "/nodes/0", "scale", json!([1e30, 1e30, 1e30])),
        _ => set(
            document,
            "",
            "animations",
            json!([{"channels": [], "samplers": []}]),
        ),
    }
}

/// One mutation of the case.
fn mutate(rng: &mut Rng, case: &mut Case) {
    match rng.below(10) {
        0..=2 => {
            let Some(at) = random_pointer(rng, &case.document) else {
                return;
            };
            let value = if rng.below(3) == 2 {
                wrong_type(rng)
            } else {
                json!(EXTREME_NUMBERS[rng.below(EXTREME_NUMBERS.len())])
            };
            *case.document.pointer_mut(&at).unwrap() = value;
        }
        3 => {
            let Some(at) = random_pointer(rng, &case.document) else {
                return;
            };
            let (parent, key) = at.rsplit_once('/').unwrap();
            match case.document.pointer_mut(parent) {
                Some(Value::Object(map)) => {
                    map.remove(&key.replace("~1", "/").replace("~0", "~"));
                }
                Some(Value::Array(items)) => {
                    items.remove(key.parse::<usize>().unwrap());
                }
                _ => {}
            }
        }
        4 => add_structure(rng, &mut case.document),
        5 | 6 => {
            // Hostile floats or indices in the buffer (positions, normals, coordinates,
            // indices and the embedded image all live there).
            if case.bin.len() >= 4 {
                let at = rng.below(case.bin.len() / 4) * 4;
                let bytes = if rng.below(2) == 0 {
                    EXTREME_FLOATS[rng.below(EXTREME_FLOATS.len())].to_le_bytes()
                } else {
                    [0xFF, 0xFF, rng.next() as u8, 0xFF]
                };
                case.bin[at..at + 4].copy_from_slice(&bytes);
            }
        }
        7 => {
            if rng.below(2) == 0 {
                let keep = rng.below(case.bin.len() + 1);
                case.bin.truncate(keep);
            } else {
                let keep = rng.below(case.image.len() + 1);
                case.image.truncate(keep);
            }
        }
        8 => case.truncate_file = Some(rng.next() as usize),
        _ => {
            for _ in 0..1 + rng.below(4) {
                case.flip_bytes
                    .push((rng.next() as usize, rng.next() as u8));
            }
        }
    }
}

/// Case `n` of the pass.
fn case(seed: u64, n: u64) -> Case {
    let mut rng = Rng(seed ^ n.wrapping_mul(0xA076_1D64_78BD_642F));
    let glb = rng.below(2) == 0;
    let (document, bin) = if glb {
        gltf_document(true, None)
    } else {
        gltf_document(false, Some("scene.bin"))
    };
    let mut case = Case {
        glb,
        document,
        bin,
        image: texture_png(),
        truncate_file: None,
        flip_bytes: Vec::new(),
    };
    for _ in 0..1 + rng.below(3) {
        mutate(&mut rng, &mut case);
    }
    case
}

/// Write the case into `dir` (replacing the previous one) and return the scene file's path.
fn write(dir: &Path, case: &Case) -> String {
    let (name, mut bytes) = if case.glb {
        ("scene.glb", glb_bytes(&case.document, case.bin.clone()))
    } else {
        std::fs::write(dir.join("scene.bin"), &case.bin).unwrap();
        std::fs::write(dir.join("texture.png"), &case.image).unwrap();
        ("scene.gltf", serde_json::to_vec(&case.document).unwrap())
    };
    if let Some(cut) = case.truncate_file {
        bytes.truncate(cut % (bytes.len() + 1));
    }
    for &(at, value) in &case.flip_bytes {
        if !bytes.is_empty() {
            let at = at % bytes.len();
            bytes[at] = value;
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn mutated_gltf_files_load_or_fail_with_one_line_never_panic() {
    let seed = env_number("VKGI_FUZZ_SEED", 0x5EED_F022);
    let cases = env_number("VKGI_FUZZ_GLTF_CASES", 5_000);
    let corpus = std::env::var_os("VKGI_FUZZ_GLTF_CORPUS").map(std::path::PathBuf::from);
    let scratch = std::env::temp_dir().join(format!("vkgi-fuzz-gltf-{}", std::process::id()));
    let mut tally = Tally::default();
    for n in 0..cases {
        let dir = match &corpus {
            Some(corpus) => corpus.join(format!("case-{n}")),
            None => scratch.clone(),
        };
        std::fs::create_dir_all(&dir).unwrap();
        let path = write(&dir, &case(seed, n));
        let loaded = quietly(|| std::panic::catch_unwind(|| Scene::load(&path)));
        tally.record(n, outcome(loaded));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    tally.assert_clean("glTF fuzz", cases, seed, "VKGI_FUZZ_SEED");
}
