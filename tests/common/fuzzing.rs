//! The fuzzing passes' shared parts: a replayable generator, hostile numbers, and the
//! invariants a loaded scene must keep whichever file format it came from.

use glam::Vec3;
use vkgi::error::InputError;
use vkgi::scene::{LightKind, MAX_COORDINATE, MAX_POWER, Scene};

/// splitmix64: a small seeded generator, so every case can be replayed from its number.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    pub fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

pub fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Numbers that break naive arithmetic.
pub const EXTREMES: &[&str] = &[
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

/// Why a loaded scene breaks an invariant the renderer relies on, if it does.
pub fn broken_invariant(scene: &Scene) -> Option<String> {
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

/// What loading one case gave: the scene (checked against every invariant) or its error line;
/// `Err` for a failure of the loader: a panic, a caught library panic, a broken invariant, or an
/// error that is not exactly one line.
pub fn outcome(
    loaded: std::thread::Result<Result<Scene, InputError>>,
) -> Result<Result<Scene, String>, String> {
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

/// Run `f` with panic messages kept off stderr (panics are what a fuzzing pass looks for).
pub fn quietly<T>(f: impl FnOnce() -> T) -> T {
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = f();
    std::panic::set_hook(previous_hook);
    result
}

/// The outcomes of a fuzzing pass: how many cases loaded, how many were refused with one line,
/// and every failure.
#[derive(Default)]
pub struct Tally {
    pub loaded: u64,
    pub refused: u64,
    pub failures: Vec<String>,
}

impl Tally {
    pub fn record(&mut self, case: u64, outcome: Result<Result<Scene, String>, String>) {
        match outcome {
            Ok(Ok(_)) => self.loaded += 1,
            Ok(Err(_)) => self.refused += 1,
            Err(why) => self.failures.push(format!("case {case}: {why}")),
        }
    }

    /// Print the tally; fail on any failure, or when the mutations never reached one of the
    /// two outcomes (a pass that only ever refuses tests nothing past the first check).
    pub fn assert_clean(&self, pass: &str, cases: u64, seed: u64, replay: &str) {
        eprintln!(
            "{pass}: {cases} cases (seed {seed:#x}): {} loaded and valid, {} refused with one line, {} failures",
            self.loaded,
            self.refused,
            self.failures.len()
        );
        assert!(
            self.failures.is_empty(),
            "{} of {cases} cases failed (replay with {replay}={seed}):\n{}",
            self.failures.len(),
            self.failures
                .iter()
                .take(20)
                .cloned()
                .collect::<Vec<_>>()
                .join("\n")
        );
        assert!(
            self.loaded > 0 && self.refused > 0,
            "the mutations exercise both outcomes"
        );
    }
}
