//! The built-in scenes, embedded in the binary so `--scene cornell` works from any directory.

use glam::Vec3;

use super::Scene;
use super::file::load_embedded;
use crate::error::InputError;

struct Builtin {
    name: &'static str,
    about: &'static str,
    scene_file: &'static str,
    obj: &'static str,
    mtl: &'static str,
}

const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "cornell",
        about: "the Cornell box (stored OBJ) under a spot light, seed 000's test scene",
        scene_file: include_str!("../../assets/scenes/cornell.toml"),
        obj: include_str!("../../assets/cornell-box.obj"),
        mtl: include_str!("../../assets/cornell-box.mtl"),
    },
    Builtin {
        name: "cornell-moving",
        about: "the Cornell box with its tall block sliding to the red wall and back (a dynamic object, a loop of 120 frames)",
        scene_file: include_str!("../../assets/scenes/cornell-moving.toml"),
        obj: include_str!("../../assets/cornell-box.obj"),
        mtl: include_str!("../../assets/cornell-box.mtl"),
    },
    Builtin {
        name: "two-rooms",
        about: "two rooms sealed by a wall, a spot light in one (stored OBJ): light in the other is a leak",
        scene_file: include_str!("../../assets/scenes/two-rooms.toml"),
        obj: include_str!("../../assets/two-rooms.obj"),
        mtl: include_str!("../../assets/two-rooms.mtl"),
    },
];

/// A built-in scene with some of its materials made glossy (the scenes that score indirect
/// specular light).
struct GlossyVariant {
    name: &'static str,
    about: &'static str,
    base: &'static str,
    /// Material name, glossy reflectance, roughness.
    gloss: &'static [(&'static str, f32, f32)],
}

const GLOSSY_VARIANTS: &[GlossyVariant] = &[
    GlossyVariant {
        name: "cornell-glossy",
        about: "cornell with glossy red and green walls (reflectance 0.3, roughness 0.3): they reflect the lit floor",
        base: "cornell",
        gloss: &[("red", 0.3, 0.3), ("green", 0.3, 0.3)],
    },
    GlossyVariant {
        name: "atrium-glossy",
        about: "atrium with glossy paving and stone (reflectance 0.3 and 0.15, roughness 0.3 and 0.5)",
        base: "atrium",
        gloss: &[("paving", 0.3, 0.3), ("stone", 0.15, 0.5)],
    },
];

/// Every built-in scene, stored or generated, with a line about it.
pub fn catalogue() -> impl Iterator<Item = (&'static str, &'static str)> {
    BUILTINS
        .iter()
        .map(|b| (b.name, b.about))
        .chain(super::generate::SCENES.iter().copied())
        .chain(GLOSSY_VARIANTS.iter().map(|v| (v.name, v.about)))
}

/// The built-in scenes' names, comma-separated.
pub fn names() -> String {
    catalogue()
        .map(|(name, _)| name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The built-in (stored or generated) scene called `name`, if there is one.
pub fn load(name: &str) -> Result<Option<Scene>, InputError> {
    if let Some(variant) = GLOSSY_VARIANTS.iter().find(|v| v.name == name) {
        let Some(mut scene) = load(variant.base)? else {
            return Ok(None);
        };
        scene.name = variant.name.to_string();
        for material in &mut scene.materials {
            if let Some(&(_, specular, roughness)) =
                variant.gloss.iter().find(|(n, _, _)| *n == material.name)
            {
                *material = material
                    .clone()
                    .with_gloss(Vec3::splat(specular), roughness);
            }
        }
        return Ok(Some(scene));
    }
    let Some(builtin) = BUILTINS.iter().find(|b| b.name == name) else {
        return super::generate::load(name);
    };
    load_embedded(builtin.name, builtin.scene_file, builtin.obj, builtin.mtl).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stored_builtin_loads_and_is_listed() {
        for name in BUILTINS.iter().map(|b| b.name) {
            assert!(catalogue().any(|(n, _)| n == name));
            let scene = load(name).unwrap().unwrap();
            assert!(scene.mesh.triangle_count() > 0);
            assert!(!scene.lights.is_empty());
        }
    }

    #[test]
    fn glossy_variants_gloss_only_their_named_materials() {
        for variant in GLOSSY_VARIANTS {
            let base = load(variant.base).unwrap().unwrap();
            let glossy = load(variant.name).unwrap().unwrap();
            assert_eq!(base.materials.len(), glossy.materials.len());
            for (b, g) in base.materials.iter().zip(&glossy.materials) {
                let named = variant.gloss.iter().any(|(n, _, _)| *n == b.name);
                assert_eq!(g.specular != Vec3::ZERO, named, "{}", b.name);
                assert_eq!(b.albedo, g.albedo);
            }
            assert!(
                variant
                    .gloss
                    .iter()
                    .all(|(n, _, _)| base.materials.iter().any(|m| m.name == *n))
            );
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
