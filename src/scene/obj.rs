//! OBJ + MTL through tobj: `Kd` is the albedo, `Ke` the emitted radiance. Non-finite vertices,
//! missing files and malformed data are input errors; zero-area triangles are skipped.

use std::io::BufReader;
use std::path::Path;

use glam::Vec3;

use super::{Material, Mesh};
use crate::error::InputError;

/// Where an OBJ comes from: the file system, or text embedded in the binary (built-in scenes).
pub enum ObjSource<'a> {
    File(&'a Path),
    Embedded {
        name: &'a str,
        obj: &'a str,
        mtl: &'a str,
    },
}

impl ObjSource<'_> {
    fn name(&self) -> String {
        match self {
            ObjSource::File(p) => p.display().to_string(),
            ObjSource::Embedded { name, .. } => (*name).to_string(),
        }
    }
}

/// Albedo of triangles without a material.
const DEFAULT_ALBEDO: f32 = 0.7;

/// Load the triangles and materials of an OBJ, scaling positions by `scale`.
pub fn load(source: &ObjSource, scale: f32) -> Result<(Mesh, Vec<Material>), InputError> {
    let name = source.name();
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let loaded = match source {
        ObjSource::File(path) => {
            if !path.is_file() {
                return Err(InputError::new(format!("{name}: no such file")));
            }
            tobj::load_obj(path, &options)
        }
        ObjSource::Embedded { obj, mtl, .. } => {
            let mut reader = BufReader::new(obj.as_bytes());
            tobj::load_obj_buf(&mut reader, &options, |_| {
                tobj::load_mtl_buf(&mut BufReader::new(mtl.as_bytes()))
            })
        }
    };
    let (models, materials) =
        loaded.map_err(|e| InputError::new(format!("{name}: malformed OBJ: {e}")))?;
    let obj_materials = materials.map_err(|e| {
        InputError::new(format!(
            "{name}: cannot load its material library (MTL): {e}"
        ))
    })?;

    let mut materials = Vec::with_capacity(obj_materials.len() + 1);
    for m in &obj_materials {
        materials.push(convert_material(&name, m)?);
    }
    let default_material = materials.len() as u32;
    let mut uses_default = false;

    let mut mesh = Mesh::default();
    let mut skipped = 0usize;
    for model in &models {
        let m = &model.mesh;
        let vertex_count = m.positions.len() / 3;
        for (v, p) in m.positions.chunks_exact(3).enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(InputError::new(format!(
                    "{name}: object '{}' vertex {} has a non-finite coordinate ({}, {}, {})",
                    model.name,
                    v + 1,
                    p[0],
                    p[1],
                    p[2]
                )));
            }
        }
        let material = match m.material_id {
            Some(id) if id < materials.len() => id as u32,
            Some(id) => {
                return Err(InputError::new(format!(
                    "{name}: object '{}' uses material {id}, which the MTL does not define",
                    model.name
                )));
            }
            None => {
                uses_default = true;
                default_material
            }
        };
        for tri in m.indices.chunks_exact(3) {
            let index = |k: usize| -> Result<usize, InputError> {
                let i = tri[k] as usize;
                if i >= vertex_count {
                    return Err(InputError::new(format!(
                        "{name}: object '{}' has a face referring to vertex {} of {vertex_count}",
                        model.name,
                        i + 1
                    )));
                }
                Ok(i)
            };
            let idx = [index(0)?, index(1)?, index(2)?];
            let position = |i: usize| {
                Vec3::new(
                    m.positions[3 * i],
                    m.positions[3 * i + 1],
                    m.positions[3 * i + 2],
                ) * scale
            };
            let p = idx.map(position);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            let longest = (p[1] - p[0])
                .length_squared()
                .max((p[2] - p[1]).length_squared())
                .max((p[0] - p[2]).length_squared());
            let degenerate = longest == 0.0 || cross.length() <= 1e-7 * longest;
            if degenerate {
                skipped += 1;
                continue;
            }
            let face_normal = cross.normalize();
            let has_normals = m.normals.len() == m.positions.len();
            for (corner, &i) in idx.iter().enumerate() {
                let n = if has_normals {
                    Vec3::new(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2])
                } else {
                    face_normal
                };
                let n = if n.is_finite() && n.length() > 1e-6 {
                    n.normalize()
                } else {
                    face_normal
                };
                mesh.positions.push(p[corner]);
                mesh.normals.push(n);
            }
            mesh.materials.push(material);
        }
    }
    if mesh.triangle_count() == 0 {
        return Err(InputError::new(format!(
            "{name}: the mesh is empty (no triangles with non-zero area)"
        )));
    }
    if skipped > 0 {
        log::warn!("{name}: skipped {skipped} zero-area triangle(s)");
    }
    if uses_default {
        materials.push(Material {
            name: "default".into(),
            albedo: Vec3::splat(DEFAULT_ALBEDO),
            emission: Vec3::ZERO,
        });
    }
    Ok((mesh, materials))
}

fn convert_material(file: &str, m: &tobj::Material) -> Result<Material, InputError> {
    let albedo = Vec3::from(m.diffuse.unwrap_or([DEFAULT_ALBEDO; 3]));
    let emission = Vec3::from(m.emissive.unwrap_or([0.0; 3]));
    if !(albedo.is_finite() && albedo.min_element() >= 0.0 && albedo.max_element() <= 1.0) {
        return Err(InputError::new(format!(
            "{file}: material '{}' has Kd {albedo}; each component must be within [0, 1]",
            m.name
        )));
    }
    if !(emission.is_finite() && emission.min_element() >= 0.0) {
        return Err(InputError::new(format!(
            "{file}: material '{}' has Ke {emission}; each component must be finite and >= 0",
            m.name
        )));
    }
    Ok(Material {
        name: m.name.clone(),
        albedo,
        emission,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn embedded(obj: &str, mtl: &str) -> Result<(Mesh, Vec<Material>), InputError> {
        load(
            &ObjSource::Embedded {
                name: "t.obj",
                obj,
                mtl,
            },
            1.0,
        )
    }

    const MTL: &str = "newmtl red\nKd 0.8 0.1 0.1\nKe 0 0 0\nnewmtl lamp\nKd 0 0 0\nKe 5 4 3\n";

    #[test]
    fn loads_quads_as_triangles_with_materials() {
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3 4\n";
        let (mesh, mats) = embedded(obj, MTL).unwrap();
        assert_eq!(mesh.triangle_count(), 2);
        assert_eq!(mats[mesh.materials[0] as usize].name, "red");
        assert!((mesh.face_normal(0) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn emission_comes_from_ke() {
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl lamp\nf 1 2 3\n";
        let (mesh, mats) = embedded(obj, MTL).unwrap();
        assert_eq!(
            mats[mesh.materials[0] as usize].emission,
            Vec3::new(5.0, 4.0, 3.0)
        );
    }

    #[test]
    fn zero_area_triangles_are_skipped() {
        let obj = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n";
        let (mesh, mats) = embedded(obj, "").unwrap();
        assert_eq!(mesh.triangle_count(), 1);
        assert_eq!(mats.last().unwrap().name, "default");
    }

    #[test]
    fn bad_meshes_are_input_errors() {
        let nan = embedded("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "").unwrap_err();
        assert!(nan.to_string().contains("non-finite"), "{nan}");
        let inf = embedded("v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", "").unwrap_err();
        assert!(inf.to_string().contains("non-finite"), "{inf}");
        let empty = embedded("# nothing\n", "").unwrap_err();
        assert!(empty.to_string().contains("empty"), "{empty}");
        let degenerate = embedded("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", "").unwrap_err();
        assert!(degenerate.to_string().contains("empty"), "{degenerate}");
        let garbage = embedded("v 0 0 zero\nf 1 2 3\n", "").unwrap_err();
        assert!(garbage.to_string().contains("malformed"), "{garbage}");
        let albedo = embedded(
            "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl hot\nf 1 2 3\n",
            "newmtl hot\nKd 1.5 0 0\n",
        )
        .unwrap_err();
        assert!(albedo.to_string().contains("Kd"), "{albedo}");
    }
}
