//! The built-in scenes, embedded in the binary so `--scene cornell` works from any directory.

use super::Scene;
use super::file::load_embedded;
use crate::error::InputError;

struct Builtin {
    name: &'static str,
    scene_file: &'static str,
    obj: &'static str,
    mtl: &'static str,
}

const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "cornell",
        scene_file: include_str!("../../assets/scenes/cornell.toml"),
        obj: include_str!("../../assets/cornell-box.obj"),
        mtl: include_str!("../../assets/cornell-box.mtl"),
    },
    Builtin {
        name: "two-rooms",
        scene_file: include_str!("../../assets/scenes/two-rooms.toml"),
        obj: include_str!("../../assets/two-rooms.obj"),
        mtl: include_str!("../../assets/two-rooms.mtl"),
    },
];

/// Names of the built-in scenes stored as files (the generated ones are in
/// [`super::generate::NAMES`]).
pub const NAMES: &[&str] = &["cornell", "two-rooms"];

/// The built-in (stored or generated) scene called `name`, if there is one.
pub fn load(name: &str) -> Result<Option<Scene>, InputError> {
    let Some(builtin) = BUILTINS.iter().find(|b| b.name == name) else {
        return super::generate::load(name);
    };
    load_embedded(builtin.name, builtin.scene_file, builtin.obj, builtin.mtl).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_loads_and_is_listed() {
        assert_eq!(NAMES.len(), BUILTINS.len());
        for name in NAMES {
            let scene = load(name).unwrap().unwrap();
            assert!(scene.mesh.triangle_count() > 0);
            assert!(!scene.lights.is_empty());
        }
    }

    #[test]
    fn cornell_has_published_dimensions() {
        let scene = load("cornell").unwrap().unwrap();
        let size = scene.bounds_max - scene.bounds_min;
        // 556 x 548.8 x 559.2 mm.
        assert!((size.x - 0.556).abs() < 1e-4, "{size}");
        assert!((size.y - 0.5488).abs() < 1e-4, "{size}");
        assert!((size.z - 0.5592).abs() < 1e-4, "{size}");
        assert_eq!(scene.mesh.triangle_count(), 5 * 2 + 2 * 5 * 2);
    }
}
