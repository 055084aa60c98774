//! A scene written back out as the files vkgi reads: an OBJ (positions, normals, texture
//! coordinates where a material is textured; each dynamic object as an object `o` of its own,
//! where its path starts from), its MTL (`Kd`, `Ke`, `Ks`, `Ns`, `map_Kd`, and `two_sided 1`, vkgi's one
//! extension of MTL), the albedo textures as PNG, and a scene file (TOML) with the camera, the
//! point and spot lights and the dynamic objects' paths. Numbers are written in Rust's shortest round-trip form,
//! so reading the files back gives the same floats (texture `v` is flipped, as OBJ counts it
//! up the image, and `1 - (1 - v)` may differ from `v` in its last bit; roughness goes through
//! the Phong exponent `Ns` and back, within 1e-5).

use std::collections::HashSet;
use std::fmt::Write;
use std::sync::Arc;

use glam::Vec3;

use super::{LightKind, Scene, Texture};

/// The files a scene becomes; every name is relative to the folder they are written into.
pub struct Exported {
    pub obj_name: String,
    pub obj: String,
    pub mtl_name: String,
    pub mtl: String,
    pub scene_file_name: String,
    pub scene_file: String,
    /// File name and texture of each distinct albedo texture.
    pub textures: Vec<(String, Arc<Texture>)>,
}

/// `name` as a file stem: letters, digits, `-` and `_` kept, anything else `-`.
pub fn file_stem(name: &str) -> String {
    let stem: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    if stem.is_empty() {
        "scene".into()
    } else {
        stem
    }
}

/// The files of `scene`, named after `stem`.
pub fn export(scene: &Scene, stem: &str) -> Exported {
    let mtl_name = format!("{stem}.mtl");
    let material_names = material_names(scene);
    let textures = distinct_textures(scene, stem);
    let textured = scene.textured();
    Exported {
        obj_name: format!("{stem}.obj"),
        obj: obj_text(scene, &mtl_name, &material_names, textured),
        mtl: mtl_text(scene, &material_names, &textures),
        mtl_name,
        scene_file_name: format!("{stem}.toml"),
        scene_file: scene_file_text(scene, &format!("{stem}.obj")),
        textures,
    }
}

/// Material names MTL can carry (no whitespace), unique.
fn material_names(scene: &Scene) -> Vec<String> {
    let mut taken = HashSet::new();
    scene
        .materials
        .iter()
        .map(|m| {
            let base: String = m
                .name
                .chars()
                .map(|c| if c.is_whitespace() { '_' } else { c })
                .collect();
            let base = if base.is_empty() {
                "material".into()
            } else {
                base
            };
            let mut name = base.clone();
            let mut k = 1;
            while !taken.insert(name.clone()) {
                k += 1;
                name = format!("{base}-{k}");
            }
            name
        })
        .collect()
}

/// Each texture the materials use, once, with the file name it is written as.
fn distinct_textures(scene: &Scene, stem: &str) -> Vec<(String, Arc<Texture>)> {
    let mut textures: Vec<(String, Arc<Texture>)> = Vec::new();
    for texture in scene
        .materials
        .iter()
        .filter_map(|m| m.albedo_texture.as_ref())
    {
        if !textures.iter().any(|(_, t)| Arc::ptr_eq(t, texture)) {
            let name = format!("{stem}-texture-{}.png", textures.len() + 1);
            textures.push((name, texture.clone()));
        }
    }
    textures
}

fn obj_text(scene: &Scene, mtl_name: &str, material_names: &[String], textured: bool) -> String {
    let mesh = &scene.mesh;
    let mut obj = format!(
        "# {} written by vkgi {}\nmtllib {mtl_name}\n",
        scene.name,
        env!("CARGO_PKG_VERSION")
    );
    obj.reserve(mesh.positions.len() * 80 + mesh.triangle_count() * 40);
    // Dynamic objects' vertices where their paths start from (offset zero).
    let mut positions = mesh.positions.clone();
    for object in &scene.dynamic {
        let range = object.vertices.start as usize..object.vertices.end as usize;
        positions[range].copy_from_slice(&object.rest);
    }
    for p in &positions {
        let _ = writeln!(obj, "v {} {} {}", p.x, p.y, p.z);
    }
    // A zero normal reads back as zero: the triangle's face normal is used there.
    for n in &mesh.normals {
        let _ = writeln!(obj, "vn {} {} {}", n.x, n.y, n.z);
    }
    if textured {
        for t in &mesh.texcoords {
            let _ = writeln!(obj, "vt {} {}", t.x, 1.0 - t.y);
        }
    }
    // Each triangle's object: a dynamic object's name, or one no dynamic object has.
    let mut fixed = String::from("static");
    while scene.dynamic.iter().any(|o| o.name == fixed) {
        fixed.push('_');
    }
    let object_of = |triangle: &[u32; 3]| {
        scene
            .dynamic
            .iter()
            .find(|o| o.vertices.contains(&triangle[0]))
            .map_or(fixed.as_str(), |o| o.name.as_str())
    };
    let (mut current, mut object) = (None, None);
    for (triangle, &material) in mesh.indices.iter().zip(&mesh.materials) {
        let named = object_of(triangle);
        if !scene.dynamic.is_empty() && object != Some(named) {
            let _ = writeln!(obj, "o {named}");
            object = Some(named);
            current = None;
        }
        if current != Some(material) {
            let _ = writeln!(obj, "usemtl {}", material_names[material as usize]);
            current = Some(material);
        }
        obj.push('f');
        for &i in triangle {
            let i = i + 1;
            if textured {
                let _ = write!(obj, " {i}/{i}/{i}");
            } else {
                let _ = write!(obj, " {i}//{i}");
            }
        }
        obj.push('\n');
    }
    obj
}

fn mtl_text(
    scene: &Scene,
    material_names: &[String],
    textures: &[(String, Arc<Texture>)],
) -> String {
    let mut mtl = String::new();
    for (material, name) in scene.materials.iter().zip(material_names) {
        let a = material.albedo;
        let e = material.emission;
        let _ = write!(
            mtl,
            "newmtl {name}\nKd {} {} {}\nKe {} {} {}\n",
            a.x, a.y, a.z, e.x, e.y, e.z
        );
        if let Some(texture) = &material.albedo_texture
            && let Some((file, _)) = textures.iter().find(|(_, t)| Arc::ptr_eq(t, texture))
        {
            let _ = writeln!(mtl, "map_Kd {file}");
        }
        if material.specular != Vec3::ZERO {
            let k = material.specular;
            let ns = super::brdf::phong_from_roughness(material.roughness);
            let _ = writeln!(mtl, "Ks {} {} {}\nNs {ns}", k.x, k.y, k.z);
        }
        if material.two_sided {
            mtl.push_str("two_sided 1\n");
        }
    }
    mtl
}

fn vector(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

fn scene_file_text(scene: &Scene, obj_name: &str) -> String {
    let c = &scene.camera;
    let mut text = format!(
        "# {} written by vkgi {}; units are metres\nmesh = \"{obj_name}\"\n\n[camera]\nposition = {}\ntarget = {}\nup = {}\nfov = {}\n",
        scene.name,
        env!("CARGO_PKG_VERSION"),
        vector(c.position),
        vector(c.target),
        vector(c.up),
        c.vfov_deg
    );
    for light in &scene.lights {
        let kind = match light.kind {
            LightKind::Point => "point",
            LightKind::Spot { .. } => "spot",
            // Samples of emissive triangles, which the OBJ and MTL carry already.
            LightKind::Cosine { .. } => continue,
        };
        let _ = write!(text, "\n[[light]]\ntype = \"{kind}\"\n");
        let _ = writeln!(text, "position = {}", vector(light.position));
        if let LightKind::Spot {
            direction,
            cone_angle_deg,
            penumbra_deg,
        } = light.kind
        {
            let _ = write!(
                text,
                "direction = {}\ncone_angle = {cone_angle_deg}\npenumbra = {penumbra_deg}\n",
                vector(direction)
            );
        }
        let _ = write!(
            text,
            "flux = {}\ncolor = {}\n",
            light.flux,
            vector(light.color)
        );
    }
    for object in &scene.dynamic {
        let keys: Vec<String> = object
            .path
            .keys()
            .iter()
            .map(|(frame, offset)| format!("{{ frame = {frame}, offset = {} }}", vector(*offset)))
            .collect();
        let _ = write!(
            text,
            "\n[[dynamic]]\nobject = {}\npath = [{}]\nloop = {}\n",
            toml::Value::String(object.name.clone()),
            keys.join(", "),
            object.path.looped()
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_stems_keep_only_safe_characters() {
        assert_eq!(file_stem("atrium:3"), "atrium-3");
        assert_eq!(file_stem("a b/c"), "a-b-c");
        assert_eq!(file_stem(""), "scene");
    }
}
