//! `--method` and its setting flags turned into a GI method: the registry entry, its validated
//! settings, and the method built with a set-up progress bar.

use crate::gi::GiMethod;
use crate::gi::registry::{self, MethodEntry, Setup};
use crate::gi::settings::Settings;
use crate::gpu::Gpu;
use crate::reference::ReferenceImages;
use crate::scene::Scene;

/// A method chosen on the command line, with its settings.
pub struct Chosen {
    pub entry: &'static MethodEntry,
    pub settings: Settings,
}

/// The method `name` with the user's setting overrides (None for `none`). Overrides that
/// `name` does not have are named in a warning (another method may use them, e.g. in the
/// viewer).
pub fn choose(name: &str, overrides: &[(String, String)]) -> anyhow::Result<Option<Chosen>> {
    let Some(entry) = registry::lookup(name)? else {
        if let Some((setting, _)) = overrides.first() {
            log::warn!("--{setting} is ignored: no GI method is used (--method none)");
        }
        return Ok(None);
    };
    let settings = entry.settings(overrides)?;
    for (setting, _) in overrides.iter().filter(|(n, _)| !settings.has(n)) {
        log::warn!("--{setting} is not a setting of {}: ignored", entry.name);
    }
    Ok(Some(Chosen { entry, settings }))
}

/// Build the chosen method, if any (None: direct light only).
pub fn build_if_chosen(
    gpu: &Gpu,
    scene: &Scene,
    chosen: Option<&Chosen>,
) -> anyhow::Result<Option<Box<dyn GiMethod>>> {
    chosen.map(|c| build(gpu, scene, c, None)).transpose()
}

/// Build the chosen method again for a changed scene (see `runner::follow`); an error without
/// one, since nothing then asks to be rebuilt.
pub fn rebuild(
    gpu: &Gpu,
    scene: &Scene,
    chosen: Option<&Chosen>,
) -> anyhow::Result<Box<dyn GiMethod>> {
    match chosen {
        Some(c) => build(gpu, scene, c, None),
        None => anyhow::bail!("no GI method to build"),
    }
}

/// Build the chosen method, showing its set-up progress.
pub fn build(
    gpu: &Gpu,
    scene: &Scene,
    chosen: &Chosen,
    reference: Option<&ReferenceImages>,
) -> anyhow::Result<Box<dyn GiMethod>> {
    let bar = super::progress::setup(chosen.entry.name);
    let progress = |stage: &str, fraction: f64| super::progress::setup_stage(&bar, stage, fraction);
    let method = chosen.entry.create(
        &Setup {
            gpu,
            scene,
            reference,
            progress: &progress,
        },
        &chosen.settings,
    );
    bar.finish_and_clear();
    method
}
