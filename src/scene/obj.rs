//! OBJ + MTL through tobj: `Kd` is the albedo (times the `map_Kd` texture, read relative to the
//! OBJ, at the `vt` coordinates), `Ke` the emitted radiance (from the front face, by winding,
//! unless the material says `two_sided 1`, vkgi's one extension of MTL). Non-finite vertices
//! (after scaling), faces of fewer than three vertices, `usemtl` of a material no MTL defines,
//! colour lines of fewer than three numbers, missing files and malformed data are input
//! errors; zero-area triangles are skipped. Both files are checked before tobj reads them (it
//! panics on some malformed MTL lines), and tobj runs behind a panic guard as a last resort.

use std::cell::RefCell;
use std::io::{BufRead, BufReader, Read};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::brdf::roughness_from_phong;
use super::{Material, Mesh, Texture};
use crate::error::{InputError, catch_library_panic};

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

/// Read a text file, as an input error when it is missing, unreadable or not UTF-8.
fn read_text(path: &Path, what: &str) -> Result<String, InputError> {
    if !path.is_file() {
        return Err(InputError::new(format!(
            "{}: no such file ({what})",
            path.display()
        )));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| InputError::new(format!("{}: cannot read {what}: {e}", path.display())))?;
    String::from_utf8(bytes)
        .map_err(|_| InputError::new(format!("{}: {what} is not UTF-8 text", path.display())))
}

/// What the OBJ's own lines say before tobj reads them: the `usemtl` names. Faces of fewer than
/// three vertices are errors (tobj would drop them silently). Reads line by line.
fn scan_obj(name: &str, reader: impl BufRead) -> Result<Vec<String>, InputError> {
    let mut used: Vec<String> = Vec::new();
    for (n, line) in reader.lines().enumerate() {
        let line = line.map_err(|e| match e.kind() {
            std::io::ErrorKind::InvalidData => {
                InputError::new(format!("{name}:{}: not UTF-8 text", n + 1))
            }
            _ => InputError::new(format!("{name}: cannot read the OBJ: {e}")),
        })?;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("f") => {
                let corners = words.count();
                if corners < 3 {
                    return Err(InputError::new(format!(
                        "{name}:{}: a face needs at least 3 vertices, this one has {corners}",
                        n + 1
                    )));
                }
            }
            Some("usemtl") => {
                let material = line.trim_start()["usemtl".len()..].trim();
                if material.is_empty() {
                    return Err(InputError::new(format!(
                        "{name}:{}: usemtl names no material",
                        n + 1
                    )));
                }
                if !used.iter().any(|u| u == material) {
                    used.push(material.to_string());
                }
            }
            _ => {}
        }
    }
    Ok(used)
}

/// Faces per object tobj parses at a time (see [`Chunked`]).
const CHUNK_FACES: usize = 1 << 16;

/// An OBJ reader that starts a new object (`o`) of the same name every [`CHUNK_FACES`] faces.
/// tobj holds every face of the current object parsed (about 100 bytes a face) until the object
/// ends, so a single-object file of two million triangles would peak at six times its size;
/// split into objects it holds one chunk. Objects keep the material in use and their name, so
/// the mesh and its named objects are unchanged.
struct Chunked<R: BufRead> {
    inner: R,
    /// Bytes read from `inner` (and injected) not yet handed out, from `at`.
    pending: Vec<u8>,
    at: usize,
    faces: usize,
    /// The `o` or `g` line that named the current object (none before the first).
    naming: Vec<u8>,
}

impl<R: BufRead> Chunked<R> {
    fn new(inner: R) -> Self {
        Chunked {
            inner,
            pending: Vec::new(),
            at: 0,
            faces: 0,
            naming: b"o\n".to_vec(),
        }
    }
}

impl<R: BufRead> Read for Chunked<R> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.pending.len() {
            self.pending.clear();
            self.at = 0;
            let mut line = Vec::new();
            if self.inner.read_until(b'\n', &mut line)? == 0 {
                return Ok(0);
            }
            let trimmed = line.trim_ascii_start();
            if trimmed.starts_with(b"o ") || trimmed.starts_with(b"g ") || trimmed == b"o" {
                self.faces = 0;
                self.naming = [b"o ", trimmed.get(2..).unwrap_or_default()].concat();
                if !self.naming.ends_with(b"\n") {
                    self.naming.push(b'\n');
                }
            } else if trimmed.starts_with(b"f ") || trimmed.starts_with(b"f\t") {
                self.faces += 1;
                if self.faces > CHUNK_FACES {
                    self.faces = 1;
                    self.pending.extend_from_slice(&self.naming);
                }
            }
            self.pending.extend_from_slice(&line);
        }
        let n = out.len().min(self.pending.len() - self.at);
        out[..n].copy_from_slice(&self.pending[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// Colour lines (`Ka`, `Kd`, `Ks`, `Ke`) must hold three values (tobj panics on fewer).
fn check_mtl(origin: &str, text: &str) -> Result<(), InputError> {
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() else {
            continue;
        };
        let values: Vec<&str> = words.collect();
        if values.len() < 3 {
            return Err(InputError::new(format!(
                "{origin}:{}: material colour {key} needs three numbers (R G B), found '{}'",
                n + 1,
                values.join(" ")
            )));
        }
    }
    Ok(())
}

/// What an OBJ holds.
#[derive(Debug)]
pub struct ObjMesh {
    pub mesh: Mesh,
    pub materials: Vec<Material>,
    /// The triangles of each object (`o`) or group (`g`), by name, in file order; a name may
    /// have several runs.
    pub objects: Vec<(String, Range<usize>)>,
}

/// The triangles of every object or group of `objects` called `name`.
pub fn triangles_of(objects: &[(String, Range<usize>)], name: &str) -> Vec<usize> {
    objects
        .iter()
        .filter(|(n, _)| n == name)
        .flat_map(|(_, r)| r.clone())
        .collect()
}

/// Load the triangles, materials and named objects of an OBJ, scaling positions by `scale`.
pub fn load(source: &ObjSource, scale: f32) -> Result<ObjMesh, InputError> {
    let name = source.name();
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let open = || -> Result<Box<dyn BufRead + '_>, InputError> {
        match source {
            ObjSource::File(path) => {
                if !path.is_file() {
                    return Err(InputError::new(format!("{name}: no such file (the OBJ)")));
                }
                let file = std::fs::File::open(path)
                    .map_err(|e| InputError::new(format!("{name}: cannot read the OBJ: {e}")))?;
                Ok(Box::new(BufReader::new(file)))
            }
            ObjSource::Embedded { obj, .. } => Ok(Box::new(obj.as_bytes())),
        }
    };
    let used_materials = scan_obj(&name, open()?)?;
    // Why a material library could not be loaded, in words (tobj only has an error code).
    let mtl_failure: RefCell<Option<InputError>> = RefCell::new(None);
    let load_mtl = |mtl_path: &Path| {
        let (origin, text) = match source {
            ObjSource::File(path) => {
                let full = path.parent().unwrap_or(Path::new(".")).join(mtl_path);
                let text = read_text(&full, "the material library its mtllib names");
                (full.display().to_string(), text)
            }
            ObjSource::Embedded { mtl, .. } => (format!("{name} (MTL)"), Ok((*mtl).to_string())),
        };
        match text.and_then(|t| check_mtl(&origin, &t).map(|()| t)) {
            Ok(text) => tobj::load_mtl_buf(&mut BufReader::new(text.as_bytes())),
            Err(e) => {
                mtl_failure.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    };
    let (models, materials) = catch_library_panic("the OBJ reader (tobj)", || {
        let mut reader = BufReader::new(Chunked::new(open()?));
        tobj::load_obj_buf(&mut reader, &options, load_mtl)
            .map_err(|e| InputError::new(format!("{name}: malformed OBJ: {e}")))
    })?;
    if let Some(e) = mtl_failure.into_inner() {
        return Err(e);
    }
    let obj_materials = materials.map_err(|e| {
        InputError::new(format!(
            "{name}: cannot load its material library (MTL): {e}"
        ))
    })?;
    if let Some(missing) = used_materials
        .iter()
        .find(|u| !obj_materials.iter().any(|m| &m.name == *u))
    {
        return Err(InputError::new(format!(
            "{name}: usemtl {missing}: no material library of the OBJ defines it"
        )));
    }

    let texture_dir = match source {
        ObjSource::File(path) => Some(path.parent().unwrap_or(Path::new("."))),
        ObjSource::Embedded { .. } => None,
    };
    let mut textures = TextureCache::default();
    let mut materials = Vec::with_capacity(obj_materials.len() + 1);
    for m in &obj_materials {
        let mut material = convert_material(&name, m)?;
        if let Some(file) = &m.diffuse_texture {
            material.albedo_texture = Some(textures.load(&name, texture_dir, file)?);
        }
        materials.push(material);
    }
    let default_material = materials.len() as u32;
    let mut uses_default = false;

    // Reserved up front: growth by doubling would hold up to twice the mesh at its peak.
    let triangles: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    let vertices: usize = models.iter().map(|m| m.mesh.positions.len() / 3).sum();
    let mut mesh = Mesh {
        positions: Vec::with_capacity(vertices),
        normals: Vec::with_capacity(vertices),
        texcoords: Vec::with_capacity(vertices),
        indices: Vec::with_capacity(triangles),
        materials: Vec::with_capacity(triangles),
    };
    let mut skipped = 0usize;
    let mut objects: Vec<(String, Range<usize>)> = Vec::new();
    for model in &models {
        let first_triangle = mesh.triangle_count();
        let m = &model.mesh;
        let vertex_count = m.positions.len() / 3;
        for (v, p) in m.positions.chunks_exact(3).enumerate() {
            let scaled = Vec3::new(p[0], p[1], p[2]) * scale;
            if !scaled.is_finite() {
                return Err(InputError::new(format!(
                    "{name}: object '{}' vertex {} has a non-finite coordinate ({}, {}, {}){}",
                    model.name,
                    v + 1,
                    p[0],
                    p[1],
                    p[2],
                    if scale == 1.0 {
                        String::new()
                    } else {
                        format!(" once scaled by {scale}")
                    }
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
        let has_normals = m.normals.len() == m.positions.len();
        let has_texcoords = m.texcoords.len() / 2 == vertex_count;
        // OBJ's v runs up the image; vkgi's (glTF's) runs down its rows.
        let texcoord = |i: usize| {
            if has_texcoords {
                Vec2::new(m.texcoords[2 * i], 1.0 - m.texcoords[2 * i + 1])
            } else {
                Vec2::ZERO
            }
        };
        if let Some(i) = (0..vertex_count).find(|&i| !texcoord(i).is_finite()) {
            return Err(InputError::new(format!(
                "{name}: object '{}' vertex {} has non-finite texture coordinates",
                model.name,
                i + 1
            )));
        }
        let position = |i: usize| {
            Vec3::new(
                m.positions[3 * i],
                m.positions[3 * i + 1],
                m.positions[3 * i + 2],
            ) * scale
        };
        // A unit normal in f64 (a huge one overflows its length in f32), or zero where the
        // file gives none or a degenerate one: the face normal is used there.
        let normal = |i: usize| {
            if !has_normals {
                return Vec3::ZERO;
            }
            let n = Vec3::new(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2])
                .as_dvec3()
                .normalize_or_zero()
                .as_vec3();
            if n.is_finite() && n.length() > 0.5 {
                n
            } else {
                Vec3::ZERO
            }
        };
        // The model's vertices become the mesh's as triangles use them, so unused vertices
        // (of skipped triangles) do not widen the bounds.
        let mut remap = vec![u32::MAX; vertex_count];
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
            // In f64: edges and their cross product of far-apart vertices overflow f32.
            let d = idx.map(|i| position(i).as_dvec3());
            let cross = (d[1] - d[0]).cross(d[2] - d[0]);
            let longest = (d[1] - d[0])
                .length_squared()
                .max((d[2] - d[1]).length_squared())
                .max((d[0] - d[2]).length_squared());
            let degenerate = longest == 0.0 || cross.length() <= 1e-7 * longest;
            if degenerate {
                skipped += 1;
                continue;
            }
            let corners = idx.map(|i| {
                if remap[i] == u32::MAX {
                    remap[i] = mesh.positions.len() as u32;
                    mesh.positions.push(position(i));
                    mesh.normals.push(normal(i));
                    mesh.texcoords.push(texcoord(i));
                }
                remap[i]
            });
            mesh.indices.push(corners);
            mesh.materials.push(material);
        }
        if mesh.triangle_count() > first_triangle {
            objects.push((model.name.clone(), first_triangle..mesh.triangle_count()));
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
        materials.push(Material::diffuse("default", Vec3::splat(DEFAULT_ALBEDO)));
    }
    Ok(ObjMesh {
        mesh,
        materials,
        objects,
    })
}

/// Textures a material library names, each read once however many materials use it.
#[derive(Default)]
struct TextureCache {
    loaded: Vec<(PathBuf, Arc<Texture>)>,
}

impl TextureCache {
    /// The texture `map_Kd` names, relative to the OBJ's folder. Options before the file name
    /// (`-s`, `-o`, ...) are ignored with a warning.
    fn load(
        &mut self,
        obj: &str,
        dir: Option<&Path>,
        map_kd: &str,
    ) -> Result<Arc<Texture>, InputError> {
        let Some(dir) = dir else {
            return Err(InputError::new(format!(
                "{obj}: map_Kd {map_kd}: a built-in scene cannot name texture files"
            )));
        };
        let file = match map_kd.trim() {
            option if option.starts_with('-') => {
                let file = option.split_whitespace().last().unwrap_or_default();
                log::warn!("{obj}: map_Kd options ignored, reading {file}");
                file
            }
            file => file,
        };
        if file.is_empty() {
            return Err(InputError::new(format!("{obj}: map_Kd names no file")));
        }
        let path = dir.join(file);
        if let Some((_, texture)) = self.loaded.iter().find(|(p, _)| *p == path) {
            return Ok(texture.clone());
        }
        let texture = Arc::new(Texture::load(&path)?);
        self.loaded.push((path, texture.clone()));
        Ok(texture)
    }
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
    let two_sided = match m.unknown_param.get("two_sided").map(|v| v.trim()) {
        None | Some("0") => false,
        Some("1") => true,
        Some(other) => {
            return Err(InputError::new(format!(
                "{file}: material '{}' has two_sided {other}; it must be 0 or 1",
                m.name
            )));
        }
    };
    Ok(Material {
        emission,
        two_sided,
        ..Material::diffuse(&m.name, albedo)
    }
    .with_gloss(
        glossy_reflectance(file, m, albedo)?,
        roughness_from_phong(m.shininess.unwrap_or(0.0)),
    ))
}

/// A material's `Ks`, lowered where `Kd + Ks` would reflect more than all light (common in
/// exported MTL files), with a warning.
fn glossy_reflectance(file: &str, m: &tobj::Material, albedo: Vec3) -> Result<Vec3, InputError> {
    let specular = Vec3::from(m.specular.unwrap_or([0.0; 3]));
    if !(specular.is_finite() && specular.min_element() >= 0.0 && specular.max_element() <= 1.0) {
        return Err(InputError::new(format!(
            "{file}: material '{}' has Ks {specular}; each component must be within [0, 1]",
            m.name
        )));
    }
    if let Some(ns) = m.shininess
        && !(ns.is_finite() && ns >= 0.0)
    {
        return Err(InputError::new(format!(
            "{file}: material '{}' has Ns {ns}; it must be finite and >= 0",
            m.name
        )));
    }
    let bounded = specular.min(Vec3::ONE - albedo);
    if bounded != specular {
        log::warn!(
            "{file}: material '{}': Kd + Ks exceeds 1, Ks lowered to {bounded}",
            m.name
        );
    }
    Ok(bounded)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn embedded_objects(obj: &str, mtl: &str) -> Result<ObjMesh, InputError> {
        load(
            &ObjSource::Embedded {
                name: "t.obj",
                obj,
                mtl,
            },
            1.0,
        )
    }

    fn embedded(obj: &str, mtl: &str) -> Result<(Mesh, Vec<Material>), InputError> {
        embedded_objects(obj, mtl).map(|o| (o.mesh, o.materials))
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
    fn emission_is_one_sided_unless_the_material_says_two_sided() {
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl lamp\nf 1 2 3\n";
        let (_, mats) = embedded(obj, MTL).unwrap();
        assert!(!mats.iter().any(|m| m.two_sided));
        let (_, mats) = embedded(obj, &format!("{MTL}two_sided 1\n")).unwrap();
        assert!(mats.iter().find(|m| m.name == "lamp").unwrap().two_sided);
        let bad = embedded(obj, &format!("{MTL}two_sided yes\n")).unwrap_err();
        assert!(bad.to_string().contains("two_sided yes"), "{bad}");
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

    #[test]
    fn mtl_colour_lines_with_fewer_than_three_numbers_are_errors_not_panics() {
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
        for mtl in [
            "newmtl a\nKd 0.5\n",
            "newmtl a\nKa 0.1 0.2\n",
            "newmtl a\nKs\n",
            "newmtl a\nKe 1 1",
            "newmtl a\nKd 0",
        ] {
            let err = embedded(obj, mtl).unwrap_err();
            assert!(
                err.to_string().contains("needs three numbers"),
                "{mtl:?}: {err}"
            );
        }
    }

    #[test]
    fn usemtl_of_a_missing_material_is_an_error() {
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl nowhere\nf 1 2 3\n";
        let err = embedded(obj, MTL).unwrap_err();
        assert!(err.to_string().contains("usemtl nowhere"), "{err}");
        let bare = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
        assert!(embedded(bare, "").is_err(), "no MTL at all defines it");
    }

    #[test]
    fn large_objects_are_read_in_chunks_into_the_same_mesh() {
        // A strip of 3 * CHUNK_FACES / 2 + 1 triangles in one object, with one material.
        let quads = 3 * CHUNK_FACES / 4 + 1;
        let mut obj = String::from("mtllib t.mtl\nusemtl red\no strip\n");
        for i in 0..=quads {
            obj.push_str(&format!("v {i} 0 0\nv {i} 1 0\n"));
        }
        for i in 0..quads {
            let (a, b) = (2 * i + 1, 2 * i + 3);
            obj.push_str(&format!("f {a} {b} {}\nf {a} {} {}\n", b + 1, b + 1, a + 1));
        }
        let loaded = embedded_objects(&obj, MTL).unwrap();
        let strip = triangles_of(&loaded.objects, "strip");
        assert_eq!(strip.len(), 2 * quads, "the name spans the chunks");
        let (mesh, materials) = (loaded.mesh, loaded.materials);
        assert_eq!(mesh.triangle_count(), 2 * quads);
        assert!(
            mesh.materials
                .iter()
                .all(|&m| materials[m as usize].name == "red")
        );
        let (min, max) = mesh.bounds();
        assert_eq!((min, max), (Vec3::ZERO, Vec3::new(quads as f32, 1.0, 0.0)));
        let area: f32 = (0..mesh.triangle_count())
            .map(|t| {
                let [a, b, c] = mesh.triangle(t);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        assert!((area - quads as f32).abs() < 1e-3, "{area}");
    }

    #[test]
    fn a_two_vertex_face_is_an_error() {
        let err = embedded("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n", "").unwrap_err();
        assert!(
            err.to_string().contains("t.obj:5: a face needs at least 3"),
            "{err}"
        );
    }

    #[test]
    fn vertices_are_checked_finite_after_scaling() {
        let obj = "v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n";
        let ok = load(
            &ObjSource::Embedded {
                name: "t.obj",
                obj,
                mtl: "",
            },
            1.0,
        );
        assert!(ok.is_ok());
        let err = load(
            &ObjSource::Embedded {
                name: "t.obj",
                obj,
                mtl: "",
            },
            1e30,
        )
        .unwrap_err();
        assert!(err.to_string().contains("once scaled by"), "{err}");
    }

    #[test]
    fn map_kd_textures_are_read_beside_the_obj_with_flipped_v_and_shared() {
        let dir = std::env::temp_dir().join(format!("vkgi-obj-texture-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("maps")).unwrap();
        let image = image::RgbaImage::from_fn(2, 1, |x, _| {
            image::Rgba([if x == 0 { 255 } else { 0 }, 0, 0, 255])
        });
        image.save(dir.join("maps/red.png")).unwrap();
        let mtl =
            "newmtl a\nKd 0.5 1 1\nmap_Kd maps/red.png\nnewmtl b\nmap_Kd -s 1 1 1 maps/red.png\n";
        std::fs::write(dir.join("t.mtl"), mtl).unwrap();
        let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.25\nvt 0.75 0.5\nvt 0 1\n\
                   usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 2/2\n";
        std::fs::write(dir.join("t.obj"), obj).unwrap();
        let ObjMesh {
            mesh, materials, ..
        } = load(&ObjSource::File(&dir.join("t.obj")), 1.0).unwrap();
        let [a, b] = [&materials[0], &materials[1]].map(|m| m.albedo_texture.clone().unwrap());
        assert!(Arc::ptr_eq(&a, &b), "one image, read once");
        assert_eq!((a.width, a.height), (2, 1));
        let corner = mesh.indices[0][0] as usize;
        assert_eq!(mesh.texcoords[corner], Vec2::new(0.25, 0.75));
        // u = 0.25 is the red texel's centre.
        assert_eq!(
            materials[0].albedo_at(Vec2::new(0.25, 0.5)),
            Vec3::new(0.5, 0.0, 0.0)
        );

        std::fs::write(
            dir.join("t.mtl"),
            "newmtl a\nmap_Kd missing.png\nnewmtl b\n",
        )
        .unwrap();
        let err = load(&ObjSource::File(&dir.join("t.obj")), 1.0).unwrap_err();
        assert!(err.0.contains("missing.png: no such file"), "{err}");
        std::fs::write(dir.join("maps/red.png"), b"not a png").unwrap();
        std::fs::write(dir.join("t.mtl"), mtl).unwrap();
        let err = load(&ObjSource::File(&dir.join("t.obj")), 1.0).unwrap_err();
        assert!(err.0.contains("red.png"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
