//! `vkgi scene --list` and `vkgi scene SCENE --write DIR`: the built-in scenes, and any scene
//! written as the files vkgi reads (src/scene/export.rs).

use std::path::Path;

use anyhow::Context;

use super::cli::SceneArgs;
use crate::error::InputError;
use crate::imageio;
use crate::scene::export::{self, Exported};
use crate::scene::{Scene, builtin};

pub fn run(args: &SceneArgs) -> anyhow::Result<()> {
    if args.list {
        let width = builtin::catalogue()
            .map(|(n, _)| n.len())
            .max()
            .unwrap_or(0);
        for (name, about) in builtin::catalogue() {
            println!("{name:width$}  {about}");
        }
        return Ok(());
    }
    let (Some(spec), Some(dir)) = (&args.scene, &args.write) else {
        return Err(InputError::new("give --list, or a SCENE and --write DIR").into());
    };
    let scene = Scene::load(spec)?;
    prepare_folder(dir)?;
    let exported = export::export(&scene, &export::file_stem(&scene.name));
    write(dir, &exported)?;
    println!(
        "{}: {} triangles, {} materials, {} textures, {} punctual light(s) -> {}",
        scene.name,
        scene.mesh.triangle_count(),
        scene.materials.len(),
        exported.textures.len(),
        scene.lights.len(),
        dir.join(&exported.scene_file_name).display()
    );
    Ok(())
}

/// Create `dir` if it is missing; refuse anything there that is not a folder.
fn prepare_folder(dir: &Path) -> Result<(), InputError> {
    match std::fs::symlink_metadata(dir) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(_) => Err(InputError::new(format!(
            "{}: exists and is not a folder",
            dir.display()
        ))),
        Err(_) => std::fs::create_dir_all(dir).map_err(|e| {
            InputError::new(format!("{}: cannot create the folder: {e}", dir.display()))
        }),
    }
}

/// Every file is checked before any is written, and each is written atomically; the scene file
/// goes last, so a scene file on disk always names a complete mesh.
fn write(dir: &Path, exported: &Exported) -> anyhow::Result<()> {
    let mut names = vec![&exported.obj_name, &exported.mtl_name];
    names.extend(exported.textures.iter().map(|(name, _)| name));
    names.push(&exported.scene_file_name);
    for name in &names {
        imageio::check_destination(&dir.join(name))?;
    }
    for (name, texture) in &exported.textures {
        let rgba: Vec<u8> = texture
            .texels
            .iter()
            .flat_map(|t| t.to_le_bytes())
            .collect();
        imageio::write_png(&dir.join(name), texture.width, texture.height, &rgba)
            .with_context(|| format!("writing texture {}", texture.name))?;
    }
    imageio::write_text(&dir.join(&exported.obj_name), &exported.obj)?;
    imageio::write_text(&dir.join(&exported.mtl_name), &exported.mtl)?;
    imageio::write_text(&dir.join(&exported.scene_file_name), &exported.scene_file)
}
