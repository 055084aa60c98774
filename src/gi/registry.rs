//! Every GI method, from the registrations at the bottom of src/gi/mod.rs. The command line's
//! `--method` values and setting flags, the viewer's method cycle and keys, and the lists and
//! grids of `vkgi report` and `vkgi profile` all come from here.

use crate::error::InputError;
use crate::gpu::Gpu;
use crate::reference::ReferenceImages;
use crate::scene::Scene;

use super::GiMethod;
use super::settings::{Setting, Settings};

/// The name that means "no GI method" (direct light only).
pub const NONE: &str = "none";

/// What a method's constructor gets.
pub struct Setup<'a> {
    pub gpu: &'a Gpu,
    pub scene: &'a Scene,
    /// A path-traced reference of the scene from its camera, when the caller has one (the
    /// report does): the constant-ambient oracle fits itself to it.
    pub reference: Option<&'a ReferenceImages>,
    /// Called during long set-up work with what is being done and the fraction done (0..=1).
    pub progress: &'a dyn Fn(&str, f64),
}

impl<'a> Setup<'a> {
    /// A set-up without a reference and without progress reports.
    pub fn new(gpu: &'a Gpu, scene: &'a Scene) -> Self {
        Setup {
            gpu,
            scene,
            reference: None,
            progress: &no_progress,
        }
    }
}

fn no_progress(_: &str, _: f64) {}

/// One registered method.
pub struct MethodEntry {
    /// `--method` value (lower case).
    pub name: &'static str,
    /// One line for `--help`, the report and the profile.
    pub description: &'static str,
    /// The method `--method` defaults to (exactly one registered method says so).
    pub default: bool,
    pub settings: &'static [Setting],
    /// Frames after a change (or from the start) until the image has settled.
    pub settle_frames: fn(&Settings) -> u32,
    /// The setting `vkgi profile` sweeps to measure cost against problem size (e.g. lattice).
    pub profile_axis: Option<&'static str>,
    pub create: fn(&Setup, &Settings) -> anyhow::Result<Box<dyn GiMethod>>,
}

impl MethodEntry {
    /// Defaults with the user's `(name, value)` overrides applied; an override naming a setting
    /// this method does not have is left to other methods (and reported by the caller).
    pub fn settings(&self, overrides: &[(String, String)]) -> Result<Settings, InputError> {
        let mut settings = Settings::defaults(self.settings)?;
        for (name, value) in overrides {
            if settings.has(name) {
                settings
                    .set(name, value)
                    .map_err(|e| InputError::new(format!("{} (method {})", e.0, self.name)))?;
            }
        }
        Ok(settings)
    }

    /// Build the method.
    pub fn create(&self, setup: &Setup, settings: &Settings) -> anyhow::Result<Box<dyn GiMethod>> {
        (self.create)(setup, settings)
    }
}

/// Every registered method, in registration order.
pub fn methods() -> impl Iterator<Item = &'static MethodEntry> {
    super::REGISTERED.iter().flat_map(|entries| entries.iter())
}

/// The method registered as `name` (case-insensitive); None for [`NONE`] or an unknown name.
pub fn find(name: &str) -> Option<&'static MethodEntry> {
    methods().find(|m| m.name.eq_ignore_ascii_case(name.trim()))
}

/// The name `--method` defaults to: the method registered as the default (`none` if nothing
/// is registered).
pub fn default_name() -> &'static str {
    methods()
        .find(|m| m.default)
        .or_else(|| methods().next())
        .map_or(NONE, |m| m.name)
}

/// The method named `name`, None for [`NONE`], or an error listing the names.
pub fn lookup(name: &str) -> Result<Option<&'static MethodEntry>, InputError> {
    if name.trim().eq_ignore_ascii_case(NONE) {
        return Ok(None);
    }
    find(name).map(Some).ok_or_else(|| {
        InputError::new(format!(
            "unknown method '{name}' (one of: {})",
            method_names().join(", ")
        ))
    })
}

/// `none` and every registered name.
pub fn method_names() -> Vec<&'static str> {
    std::iter::once(NONE)
        .chain(methods().map(|m| m.name))
        .collect()
}

/// Every distinct setting name across methods, with its first declaration and the methods
/// that declare it (methods may share a setting name, e.g. a lattice size).
pub fn all_settings() -> Vec<(&'static Setting, Vec<&'static str>)> {
    let mut all: Vec<(&'static Setting, Vec<&'static str>)> = Vec::new();
    for method in methods() {
        for setting in method.settings {
            match all.iter_mut().find(|(s, _)| s.name == setting.name) {
                Some((_, users)) => users.push(method.name),
                None => all.push((setting, vec![method.name])),
            }
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gi::settings::Kind;

    #[test]
    fn names_are_unique_lower_case_and_one_method_is_the_default() {
        let names: Vec<&str> = methods().map(|m| m.name).collect();
        for (i, name) in names.iter().enumerate() {
            assert_eq!(*name, name.to_lowercase());
            assert!(!names[..i].contains(name), "{name} registered twice");
            assert_ne!(*name, NONE);
        }
        assert_eq!(methods().filter(|m| m.default).count(), 1);
        assert!(find(default_name()).is_some_and(|m| m.default));
    }

    #[test]
    fn every_default_is_valid_and_shared_settings_agree_on_their_kind() {
        for method in methods() {
            let settings = match Settings::defaults(method.settings) {
                Ok(s) => s,
                Err(e) => panic!("{}: {e}", method.name),
            };
            assert!((method.settle_frames)(&settings) >= 1, "{}", method.name);
            if let Some(axis) = method.profile_axis {
                assert!(settings.has(axis), "{}: profile axis {axis}", method.name);
            }
            for setting in method.settings {
                for value in setting.sweep {
                    assert!(setting.parse(value).is_ok(), "{}: {value}", setting.name);
                }
            }
        }
        for (setting, users) in all_settings() {
            for method in users.iter().filter_map(|u| find(u)) {
                let Some(other) = method.settings.iter().find(|s| s.name == setting.name) else {
                    panic!("{} lost {}", method.name, setting.name);
                };
                let flag = |k: Kind| matches!(k, Kind::Flag);
                assert_eq!(
                    flag(setting.kind),
                    flag(other.kind),
                    "--{} is a flag in one method and takes a value in another",
                    setting.name
                );
            }
        }
    }

    #[test]
    fn unknown_names_list_the_methods() {
        assert!(matches!(lookup("NONE"), Ok(None)));
        let err = match lookup("magic") {
            Ok(_) => panic!("magic is not a method"),
            Err(e) => e,
        };
        assert!(err.0.contains("none") && err.0.contains(default_name()));
    }
}
