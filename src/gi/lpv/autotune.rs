//! `--kernel auto`: which propagation kernel runs is measured on the device, once, and kept.
//!
//! The tiled kernel (a shared-memory tile per workgroup) suits GPUs; the column kernel (a
//! column of cells per thread, its sources in registers) suits CPU devices such as lavapipe,
//! where every load is made lane by lane. Both compute the same bits (tests/lpv.rs), so the
//! choice changes only speed, never an image or a CAVE node's lattice digest.
//!
//! The first lattice a process builds on a device times one propagation of every colour channel
//! with each kernel (a warm-up, then the fastest of five) and takes the faster. The choice is
//! kept for the process and in `kernels.json` in vkgi's cache folder (`$VKGI_CACHE_DIR`, else
//! `$XDG_CACHE_HOME/vkgi`, else `~/.cache/vkgi`), keyed by the device, its driver, the scheme,
//! the lattice size (small lattices favour tiles: a column kernel there has one-cell columns),
//! the geometry words and the kernels' SPIR-V, so later runs skip the measurement and a new
//! build or driver measures again. A cache that cannot be read or written is measured around.

use std::collections::HashMap;
use std::path::PathBuf;
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
    /// "tiled" or "column".
    pub kernel: String,
    /// Milliseconds of one propagation step of all three channels, per kernel measured.
    pub tiled_ms: f64,
    pub column_ms: f64,
    /// The lattice side it was measured at.
    pub lattice: u32,
    /// Where it came from this time: "measured", "cached in PATH" or "this process".
    #[serde(skip)]
    pub source: String,
}

impl Choice {
    pub fn kernel(&self) -> Kernel {
        if self.kernel == "column" {
            Kernel::Column
        } else {
            Kernel::Tiled
        }
    }

    /// One line for the profile.
    pub fn describe(&self) -> String {
        format!(
            "chosen by --kernel auto: {} (one step of all channels at lattice {}: tiled {:.2} ms, column {:.2} ms; {})",
            self.kernel, self.lattice, self.tiled_ms, self.column_ms, self.source
        )
    }
}

/// The kernel `--kernel auto` runs for `settings` on `setup`'s device.
pub fn choose(setup: &Setup, settings: &LpvSettings) -> anyhow::Result<Choice> {
    let key = cache_key(setup, settings);
    static CHOSEN: OnceLock<Mutex<HashMap<String, Choice>>> = OnceLock::new();
    let chosen = CHOSEN.get_or_init(Default::default);
    if let Some(choice) = chosen.lock().ok().and_then(|m| m.get(&key).cloned()) {
        return Ok(Choice {
            source: "chosen earlier in this process".into(),
            ..choice
        });
    }
    let path = cache_file();
    let choice = match path.as_ref().and_then(|p| read_cache(p).remove(&key)) {
        Some(cached) => Choice {
            source: format!("cached in {}", path.as_ref().map_or(String::new(), |p| p.display().to_string())),
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
    if let Ok(mut m) = chosen.lock() {
        m.insert(key, choice.clone());
    }
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
    let mut lattices = [probe(Kernel::Tiled)?, probe(Kernel::Column)?];
    let mut best = [f64::INFINITY; 2];
    // Runs alternate between the kernels, so a machine that slows for a while slows both.
    for run in 0..=RUNS {
        for (k, lpv) in lattices.iter_mut().enumerate() {
            let start = Instant::now();
            setup.gpu.one_shot(|rec| lpv.record_propagation(rec))?;
            let ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(STEPS);
            if run > 0 {
                best[k] = best[k].min(ms);
            }
        }
    }
    Ok(Choice {
        kernel: if best[1] < best[0] { "column" } else { "tiled" }.into(),
        tiled_ms: best[0],
        column_ms: best[1],
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

fn read_cache(path: &PathBuf) -> HashMap<String, Choice> {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default()
}

/// Add `choice` under `key`; the file is replaced whole (written beside it, then renamed), so a
/// reader never sees half of it.
fn write_cache(path: &PathBuf, key: &str, choice: &Choice) -> std::io::Result<()> {
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
