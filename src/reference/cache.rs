//! The reference cache: `reference` writes its settings next to the image (`ref.exr.json`); a
//! later run with the same scene, settings and code version reuses the image instead of
//! re-rendering it.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{ReferenceImages, ReferenceSettings};
use crate::digest::{FNV_OFFSET, fnv1a};
use crate::imageio::{self, HdrImage};
use crate::scene::Scene;

/// Everything that decides a reference image's pixels.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CacheKey {
    pub scene: String,
    /// FNV-1a of the scene's geometry, materials, lights and camera.
    pub scene_hash: String,
    pub settings: ReferenceSettings,
    /// FNV-1a of the path tracer's SPIR-V and the estimator's version.
    pub code_version: String,
}

/// The sidecar written next to a reference image.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CacheRecord {
    pub key: CacheKey,
    /// Whether the direct and indirect parts were written beside the image.
    pub split: bool,
    pub seconds: f64,
    pub device: String,
}

/// Bumped whenever the estimator's meaning changes without the shader or the CPU estimator's
/// source changing.
const ESTIMATOR_VERSION: &str = "vkgi-reference-1";

/// The code a reference came from: the shader's SPIR-V and the CPU estimator's source (either
/// may have traced it; both are the same estimator), and [`ESTIMATOR_VERSION`].
pub fn code_version() -> String {
    let h = fnv1a(
        crate::shaders::REFERENCE_PATHTRACE_COMP.iter().copied(),
        FNV_OFFSET,
    );
    let h = fnv1a(include_str!("cpu.rs").bytes(), h);
    format!("{:016x}", fnv1a(ESTIMATOR_VERSION.bytes(), h))
}

pub fn scene_hash(scene: &Scene) -> String {
    let mut floats: Vec<f32> = Vec::new();
    let mesh = &scene.mesh;
    for ((p, n), uv) in mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .zip(&mesh.texcoords)
    {
        floats.extend(p.to_array());
        floats.extend(n.to_array());
        floats.extend(uv.to_array());
    }
    for (t, m) in scene.mesh.indices.iter().zip(&scene.mesh.materials) {
        floats.extend(t.map(|i| i as f32));
        floats.push(*m as f32);
    }
    for m in &scene.materials {
        floats.extend(m.albedo.to_array());
        floats.extend(m.emission.to_array());
        floats.push(f32::from(u8::from(m.two_sided)));
        // Lambertian materials hash as before the glossy lobe existed (their images are unchanged).
        if m.specular != glam::Vec3::ZERO {
            floats.extend(m.specular.extend(m.roughness).to_array());
        }
    }
    for l in &scene.lights {
        floats.extend(l.position.to_array());
        floats.extend(l.intensity().to_array());
        let (outer, inner) = l.cone_cosines();
        floats.extend([outer, inner]);
        if let Some(direction) = l.axis() {
            floats.extend(direction.to_array());
        }
    }
    let c = &scene.camera;
    floats.extend(c.position.to_array());
    floats.extend(c.target.to_array());
    floats.extend(c.up.to_array());
    floats.push(c.vfov_deg);
    let mut hash = fnv1a(floats.iter().flat_map(|f| f.to_le_bytes()), FNV_OFFSET);
    hash = fnv1a(
        scene.mesh.materials.iter().flat_map(|m| m.to_le_bytes()),
        hash,
    );
    let (textures, indices) = scene.textures();
    hash = fnv1a(
        indices
            .iter()
            .flat_map(|i| i.map_or(0, |i| i + 1).to_le_bytes()),
        hash,
    );
    for t in textures {
        hash = fnv1a(
            [t.width, t.height].iter().flat_map(|v| v.to_le_bytes()),
            hash,
        );
        hash = fnv1a(t.texels.iter().flat_map(|v| v.to_le_bytes()), hash);
    }
    format!("{hash:016x}")
}

pub fn key(scene: &Scene, settings: &ReferenceSettings) -> CacheKey {
    CacheKey {
        scene: scene.name.clone(),
        scene_hash: scene_hash(scene),
        settings: settings.clone(),
        code_version: code_version(),
    }
}

/// `ref.exr` -> `ref.exr.json`.
pub fn sidecar_path(image: &Path) -> PathBuf {
    let mut name = image.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// `ref.exr` -> `ref.direct.exr` / `ref.indirect.exr`.
pub fn split_path(image: &Path, part: &str) -> PathBuf {
    let stem = image
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    image.with_file_name(format!("{stem}.{part}.exr"))
}

/// Write the image at `path` (and its direct and indirect parts when `record.split`), then the
/// sidecar.
pub fn store(path: &Path, images: &ReferenceImages, record: &CacheRecord) -> anyhow::Result<()> {
    if record.split {
        imageio::write_exr(&split_path(path, "direct"), &images.direct)?;
        imageio::write_exr(&split_path(path, "indirect"), &images.indirect)?;
    }
    imageio::write_exr(path, &images.combined())?;
    // The sidecar goes last: its presence says the images beside it are complete.
    imageio::write_text(&sidecar_path(path), &serde_json::to_string_pretty(record)?)
}

/// The cached direct and indirect images at `path` if its sidecar matches `key` exactly and
/// the parts were written (`--split`).
pub fn load(path: &Path, key: &CacheKey) -> Option<ReferenceImages> {
    let text = std::fs::read_to_string(sidecar_path(path)).ok()?;
    let record: CacheRecord = serde_json::from_str(&text).ok()?;
    if &record.key != key || !record.split {
        return None;
    }
    let read = |p: PathBuf| -> Option<HdrImage> { imageio::read_hdr(&p, false).ok() };
    let direct = read(split_path(path, "direct"))?;
    let indirect = read(split_path(path, "indirect"))?;
    let size_ok = |i: &HdrImage| i.width == key.settings.width && i.height == key.settings.height;
    (size_ok(&direct) && size_ok(&indirect)).then_some(ReferenceImages { direct, indirect })
}
