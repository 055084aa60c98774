//! `--kernel auto`: which propagation kernel runs is measured on the device, once, and kept.
//!
//! The tiled kernel (a shared-memory tile per workgroup) suits GPUs; the column kernel (a
//! column of cells per thread, its sources in registers) suits CPU devices such as lavapipe,
//! where every load is made lane by lane. Both do the same arithmetic in the same order, and on
//! lavapipe give the same bits (tests/lpv.rs asserts it), so there the choice changes only speed.
//! A driver that contracted the two modules' arithmetic differently could differ in the last
//! bits; a CAVE whose nodes must agree bit for bit can pin `--kernel`.
//!
//! The first lattice of its kind (scheme, lattice size, geometry words) a process builds on a
//! device times a short propagation of every colour channel with each kernel (alternating, a
//! warm-up, then the fastest of five) and takes the faster; a kernel that cannot be built there
//! (no tile fits the shared memory, say) is not a candidate. The choice is kept for the process
//! and in `kernels.json` in vkgi's cache folder (`$VKGI_CACHE_DIR`, else
//! `$XDG_CACHE_HOME/vkgi`, else `~/.cache/vkgi`), keyed by the device, its driver, the scheme,
//! the lattice size (small lattices favour tiles: a column kernel there has one-cell columns),
//! the geometry words and the kernels' SPIR-V, so later runs skip the measurement and a new
//! build or driver measures again. A cache that cannot be read or written is measured around.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use super::technique::{Field, Kernel, Lpv, LpvSettings, Scheme};
use crate::gi::registry::Setup;
use crate::shaders;

/// Measured propagations per kernel (after one warm-up); the fastest counts.
const RUNS: usize = 5;
/// Steps of each measured propagation.
const STEPS: u32 = 2;

/// The autotune's choice and what it rests on.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Choice {
    pub kernel: Kernel,
    /// Milliseconds of one propagation step of all three channels, per kernel measured.
    pub tiled_ms: f64,
    pub column_ms: f64,
    /// The lattice side it was measured at.
    pub lattice: u32,
    /// Where it came from this time: "measured now", "cached in PATH" or "chosen earlier in
    /// this process".
    #[serde(skip)]
    pub source: String,
}

impl Choice {
    /// One line for the profile.
    pub fn describe(&self) -> String {
        format!(
            "chosen by --kernel auto: {} (one step of all channels at lattice {}: tiled {:.2} ms, column {:.2} ms; {})",
            format!("{:?}", self.kernel).to_lowercase(),
            self.lattice,
            self.tiled_ms,
            self.column_ms,
            self.source
        )
    }
}

/// The kernel `--kernel auto` runs for `settings` on `setup`'s device.
pub fn choose(setup: &Setup, settings: &LpvSettings) -> anyhow::Result<Choice> {
    let key = cache_key(setup, settings);
    // One lock over look-up, measurement and write: two threads never time kernels at once (nor
    // against each other), nor write the cache file together.
    static CHOSEN: OnceLock<Mutex<HashMap<String, Choice>>> = OnceLock::new();
    let mut chosen = CHOSEN
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(choice) = chosen.get(&key) {
        return Ok(Choice {
            source: "chosen earlier in this process".into(),
            ..choice.clone()
        });
    }
    let path = cache_file();
    let choice = match path.as_deref().and_then(|p| read_cache(p).remove(&key)) {
        Some(cached) => Choice {
            source: format!("cached in {}", path.as_deref().unwrap_or(Path::new("")).display()),
            ..cached
        },
        None => {
            let measured = measure(setup, settings)?;
            if let Some(path) = &path
                && let Err(e) = write_cache(path, &key, &measured)
            {
                log::warn!("kernel autotune: not cached in {}: {e}", path.display());
            }
            measured
        }
    };
    chosen.insert(key, choice.clone());
    Ok(choice)
}

/// Time a propagation of [`STEPS`] steps of every channel with each kernel on a lattice of
/// these settings.
fn measure(setup: &Setup, settings: &LpvSettings) -> anyhow::Result<Choice> {
    let probe = |kernel| {
        let settings = LpvSettings {
            kernel: Some(kernel),
            iterations: STEPS,
            ..settings.clone()
        };
        Lpv::with_field(setup, settings, Field::Whole)
    };
    // A kernel that cannot be built on this device (or for this lattice) is no candidate.
    let mut candidates: Vec<(Kernel, Lpv, f64)> = Vec::new();
    let mut refused = None;
    for kernel in [Kernel::Tiled, Kernel::Column] {
        match probe(kernel) {
            Ok(lpv) => candidates.push((kernel, lpv, f64::INFINITY)),
            Err(e) => refused = Some(e),
        }
    }
    if let (true, Some(e)) = (candidates.is_empty(), refused) {
        return Err(e);
    }
    // Runs alternate between the kernels, so a machine that slows for a while slows both.
    for run in 0..=RUNS {
        for (_, lpv, best) in &mut candidates {
            let start = Instant::now();
            setup.gpu.one_shot(|rec| lpv.record_propagation(rec))?;
            let ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(STEPS);
            if run > 0 {
                *best = best.min(ms);
            }
        }
    }
    let time = |kernel| {
        candidates
            .iter()
            .find(|c| c.0 == kernel)
            .map_or(f64::INFINITY, |c| c.2)
    };
    let (tiled_ms, column_ms) = (time(Kernel::Tiled), time(Kernel::Column));
    Ok(Choice {
        kernel: if column_ms < tiled_ms {
            Kernel::Column
        } else {
            Kernel::Tiled
        },
        tiled_ms,
        column_ms,
        lattice: settings.lattice,
        source: "measured now".into(),
    })
}

fn cache_key(setup: &Setup, settings: &LpvSettings) -> String {
    let info = &setup.gpu.info;
    let kernels: &[&[u8]] = match settings.scheme {
        Scheme::Ilpv => &[shaders::GI_LPV_ILPV_TILED_COMP, shaders::GI_LPV_ILPV_COLUMN_COMP],
        Scheme::Lpv => &[shaders::GI_LPV_LPV_TILED_COMP, shaders::GI_LPV_LPV_COLUMN_COMP],
    };
    let spirv = kernels.iter().fold(crate::digest::FNV_OFFSET, |h, k| {
        crate::digest::fnv1a(k.iter().copied(), h)
    });
    format!(
        "{} | {} | {:?} | lattice {} | {} words | {spirv:016x}",
        info.name,
        info.driver,
        settings.scheme,
        settings.lattice,
        settings.blocking_lobe.words_per_cell()
    )
}

/// vkgi's cache folder's `kernels.json`, if the environment names a folder.
fn cache_file() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    let folder = var("VKGI_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|p| p.join("vkgi")))
        .or_else(|| var("HOME").map(|p| p.join(".cache").join("vkgi")))?;
    Some(folder.join("kernels.json"))
}

fn read_cache(path: &Path) -> HashMap<String, Choice> {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default()
}

/// Add `choice` under `key`; the file is replaced whole (written beside it, then renamed), so a
/// reader never sees half of it.
fn write_cache(path: &Path, key: &str, choice: &Choice) -> std::io::Result<()> {
    let mut all = read_cache(path);
    all.insert(key.to_string(), choice.clone());
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)?;
    }
    let text = serde_json::to_string_pretty(&all).map_err(std::io::Error::other)?;
    let temporary = path.with_extension(format!("json.{}", std::process::id()));
    std::fs::write(&temporary, text)?;
    std::fs::rename(&temporary, path)
}
