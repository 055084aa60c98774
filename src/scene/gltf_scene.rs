//! glTF 2.0 scenes (`.gltf` with embedded or external buffers, `.glb`) through the `gltf` crate:
//! triangle meshes under their nodes' transforms, base colour factor and texture as the albedo,
//! emissive factor (times `KHR_materials_emissive_strength`) as emitted radiance in
//! W/(m²·sr), `doubleSided` as two-sided emission, `KHR_lights_punctual` point and spot lights
//! (candela to W/sr at 683 lm/W), and the first camera of the scene. Units are metres, as in
//! glTF. Features vkgi does not model are ignored with one warning line each.

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::khr_lights_punctual::Kind;

use super::gltf_guard;
use super::texture::linear_to_srgb;
use super::{Camera, Light, LightKind, Material, Mesh, Scene, Texture};
use crate::error::{InputError, catch_library_panic};

/// Luminous efficacy vkgi converts photometric glTF light units with (lm/W, at 555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Deepest node hierarchy read (deeper is taken as a malformed file).
const MAX_NODE_DEPTH: usize = 256;

/// Extensions vkgi reads; any other the file uses is named in a warning.
const SUPPORTED_EXTENSIONS: &[&str] = &["KHR_lights_punctual", "KHR_materials_emissive_strength"];

/// Load a `.gltf` or `.glb` file as a scene.
pub fn load(path: &Path) -> Result<Scene, InputError> {
    let name = path.display().to_string();
    if !path.is_file() {
        return Err(InputError::new(format!(
            "{name}: no such file (a glTF scene)"
        )));
    }
    gltf_guard::check(path, &name)?;
    let (document, buffers, images) =
        catch_library_panic(&format!("{name}: the glTF reader"), || {
            gltf::import(path).map_err(|e| InputError::new(format!("{name}: {}", describe(&e))))
        })?;
    let mut reader = Reader {
        name: &name,
        buffers: &buffers,
        images: &images,
        textures: vec![None; images.len()],
        warnings: BTreeSet::new(),
        mesh: Mesh::default(),
        materials: Vec::new(),
        material_of: vec![None; document.materials().len()],
        lights: Vec::new(),
        camera: None,
        skipped: 0,
    };
    for extension in document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&extension) {
            reader.warn(format!(
                "extension {extension} is not supported and is ignored"
            ));
        }
    }
    if document.animations().next().is_some() {
        reader.warn("animations are ignored (the scene is read at rest)".into());
    }
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| InputError::new(format!("{name}: the file has no scene")))?;
    reader.read_nodes(scene.nodes())?;
    let Reader {
        warnings,
        mesh,
        materials,
        lights,
        camera,
        skipped,
        ..
    } = reader;
    let mut warnings: Vec<String> = warnings.into_iter().collect();
    if skipped > 0 {
        warnings.push(format!("skipped {skipped} zero-area triangle(s)"));
    }
    if mesh.triangle_count() == 0 {
        return Err(InputError::new(format!(
            "{name}: the scene has no triangles (with non-zero area)"
        )));
    }
    let scene_name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let (min, max) = mesh.bounds();
    let emissive = materials.iter().any(|m| m.emission.max_element() > 0.0);
    let lights = if lights.is_empty() && !emissive {
        warnings.push("no light; adding a point light above the scene".into());
        vec![super::framing_light(min, max)]
    } else {
        lights
    };
    let camera = camera.unwrap_or_else(|| Camera::framing(min, max));
    let scene = Scene::new(scene_name, mesh, materials, lights, camera)?;
    // Warnings only for a scene that loads: a refused file gets its one error line alone.
    for warning in &warnings {
        log::warn!("{name}: {warning}");
    }
    Ok(scene)
}

/// One line for a gltf error (its validation errors are listed on one line already; the first
/// three are kept).
fn describe(error: &gltf::Error) -> String {
    match error {
        gltf::Error::Validation(errors) => {
            let listed: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(path, e)| format!("{path}: {e}"))
                .collect();
            let more = errors.len().saturating_sub(3);
            let more = if more > 0 {
                format!(" (and {more} more)")
            } else {
                String::new()
            };
            format!("invalid glTF: {}{more}", listed.join("; "))
        }
        gltf::Error::Io(e) => format!("cannot read a file the glTF names: {e}"),
        other => format!("malformed glTF: {}", other.to_string().replace('\n', " ")),
    }
}

struct Reader<'a> {
    name: &'a str,
    buffers: &'a [gltf::buffer::Data],
    images: &'a [gltf::image::Data],
    /// Each glTF image as a texture, converted when a material first uses it.
    textures: Vec<Option<Arc<Texture>>>,
    /// Distinct warnings, printed once each after reading.
    warnings: BTreeSet<String>,
    mesh: Mesh,
    materials: Vec<Material>,
    /// vkgi material of each glTF material, made when a primitive first uses it.
    material_of: Vec<Option<u32>>,
    lights: Vec<Light>,
    camera: Option<Camera>,
    skipped: usize,
}

impl Reader<'_> {
    fn warn(&mut self, message: String) {
        self.warnings.insert(message);
    }

    fn error(&self, message: String) -> InputError {
        InputError::new(format!("{}: {message}", self.name))
    }

    /// Walk the node trees depth first, each node under its parents' transforms.
    fn read_nodes<'d>(
        &mut self,
        roots: impl Iterator<Item = gltf::Node<'d>>,
    ) -> Result<(), InputError> {
        let mut visited = BTreeSet::new();
        let mut stack: Vec<(gltf::Node<'d>, Mat4, usize)> =
            roots.map(|n| (n, Mat4::IDENTITY, 0)).collect();
        stack.reverse();
        while let Some((node, parent, depth)) = stack.pop() {
            if !visited.insert(node.index()) {
                return Err(self.error(format!(
                    "node {} is reached twice (glTF nodes form a tree)",
                    node.index()
                )));
            }
            if depth > MAX_NODE_DEPTH {
                return Err(self.error(format!(
                    "the node hierarchy is deeper than {MAX_NODE_DEPTH} levels"
                )));
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let world = parent * local;
            if !world.is_finite() {
                return Err(self.error(format!("node {} has a non-finite transform", node.index())));
            }
            if node.skin().is_some() {
                self.warn("skins are ignored (meshes are read in their bind pose)".into());
            }
            if let Some(mesh) = node.mesh() {
                self.read_mesh(&mesh, world)?;
            }
            if let Some(light) = node.light() {
                self.read_light(&light, world);
            }
            if let (None, Some(camera)) = (&self.camera, node.camera()) {
                self.read_camera(&camera, world);
            }
            let children: Vec<_> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world, depth + 1));
            }
        }
        Ok(())
    }

    fn read_mesh(&mut self, mesh: &gltf::Mesh, world: Mat4) -> Result<(), InputError> {
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        // A mirroring transform turns the winding (glTF: the determinant decides the front).
        let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                self.warn(format!(
                    "primitives drawn as {:?} are ignored (only triangle lists are read)",
                    primitive.mode()
                ));
                continue;
            }
            if primitive.morph_targets().next().is_some() {
                self.warn("morph targets are ignored (meshes are read at rest)".into());
            }
            let (material, texcoord_set) = self.material(&primitive.material())?;
            let buffers = self.buffers;
            let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let Some(positions) = reader.read_positions() else {
                self.warn("primitives without positions are ignored".into());
                continue;
            };
            let positions: Vec<Vec3> = positions
                .map(|p| world.transform_point3(Vec3::from(p)))
                .collect();
            if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
                return Err(self.error(format!(
                    "mesh '{}' vertex {i} is not finite once transformed",
                    mesh.name().unwrap_or("unnamed")
                )));
            }
            let normals: Option<Vec<Vec3>> = reader.read_normals().map(|n| {
                n.map(|n| {
                    let n = (normal_matrix * Vec3::from(n))
                        .as_dvec3()
                        .normalize_or_zero();
                    if n.is_finite() {
                        n.as_vec3()
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect()
            });
            let texcoords: Option<Vec<Vec2>> = match texcoord_set {
                Some(set) => reader
                    .read_tex_coords(set)
                    .map(|t| t.into_f32().map(Vec2::from).collect()),
                None => None,
            };
            if let Some(t) = &texcoords
                && t.iter().any(|uv| !uv.is_finite())
            {
                return Err(self.error("texture coordinates must be finite".into()));
            }
            let count = positions.len();
            let indices: Vec<u32> = match reader.read_indices() {
                Some(indices) => indices.into_u32().collect(),
                None => (0..count as u32).collect(),
            };
            if !indices.len().is_multiple_of(3) {
                self.warn("a triangle list's last incomplete triangle is ignored".into());
            }
            let triangles = self.mesh.triangle_count() + indices.len() / 3;
            if triangles > super::MAX_TRIANGLES {
                return Err(self.error(format!(
                    "the scene has over {} triangles, vkgi's limit",
                    super::MAX_TRIANGLES
                )));
            }
            let mut remap = vec![u32::MAX; count];
            for tri in indices.chunks_exact(3) {
                let mut corners = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
                if let Some(&bad) = corners.iter().find(|&&i| i >= count) {
                    return Err(self.error(format!(
                        "mesh '{}' refers to vertex {bad} of {count}",
                        mesh.name().unwrap_or("unnamed")
                    )));
                }
                if mirrored {
                    corners.swap(1, 2);
                }
                let d = corners.map(|i| positions[i].as_dvec3());
                let cross = (d[1] - d[0]).cross(d[2] - d[0]);
                let longest = (d[1] - d[0])
                    .length_squared()
                    .max((d[2] - d[1]).length_squared())
                    .max((d[0] - d[2]).length_squared());
                if longest == 0.0 || cross.length() <= 1e-7 * longest {
                    self.skipped += 1;
                    continue;
                }
                let corners = corners.map(|i| {
                    if remap[i] == u32::MAX {
                        remap[i] = self.mesh.positions.len() as u32;
                        self.mesh.positions.push(positions[i]);
                        let normal = normals.as_ref().and_then(|n| n.get(i).copied());
                        self.mesh.normals.push(normal.unwrap_or(Vec3::ZERO));
                        let uv = texcoords.as_ref().and_then(|t| t.get(i).copied());
                        self.mesh.texcoords.push(uv.unwrap_or(Vec2::ZERO));
                    }
                    remap[i]
                });
                self.mesh.indices.push(corners);
                self.mesh.materials.push(material);
            }
        }
        Ok(())
    }

    /// The vkgi material of a glTF material (made on first use) and the texture-coordinate
    /// set its base colour texture reads, if it has one.
    fn material(&mut self, material: &gltf::Material) -> Result<(u32, Option<u32>), InputError> {
        let pbr = material.pbr_metallic_roughness();
        let texture = pbr.base_color_texture();
        let set = texture.as_ref().map(|t| t.tex_coord());
        if let Some(&Some(index)) = material.index().and_then(|i| self.material_of.get(i)) {
            return Ok((index, set));
        }
        let [r, g, b, _] = pbr.base_color_factor();
        let emission =
            Vec3::from(material.emissive_factor()) * material.emissive_strength().unwrap_or(1.0);
        let name = material
            .name()
            .map(str::to_string)
            .or_else(|| material.index().map(|i| format!("material {i}")))
            .unwrap_or_else(|| "default".into());
        if pbr.metallic_roughness_texture().is_some() {
            self.warn(
                "metallic-roughness textures are ignored (the metallic and roughness factors are used)"
                    .into(),
            );
        }
        if material.normal_texture().is_some() {
            self.warn("normal maps are ignored".into());
        }
        if material.occlusion_texture().is_some() {
            self.warn("occlusion maps are ignored".into());
        }
        if material.emissive_texture().is_some() {
            self.warn("emissive textures are ignored (the emissive factor is used)".into());
        }
        if material.alpha_mode() != gltf::material::AlphaMode::Opaque {
            self.warn("alpha blending and masking are ignored (surfaces are opaque)".into());
        }
        if texture.is_some() && pbr.metallic_factor() > 0.0 {
            self.warn(
                "a base-colour texture colours only the diffuse part of a metallic material (its glossy lobe takes the factor)"
                    .into(),
            );
        }
        let albedo_texture = match texture {
            Some(info) => {
                let sampler = info.texture().sampler();
                if sampler.wrap_s() != gltf::texture::WrappingMode::Repeat
                    || sampler.wrap_t() != gltf::texture::WrappingMode::Repeat
                {
                    self.warn("clamped and mirrored texture wrapping are sampled as repeat".into());
                }
                Some(self.texture(info.texture().source().index())?)
            }
            None => None,
        };
        // The metallic-roughness model: metals reflect their base colour glossily, dielectrics
        // diffusely with a 4% glossy lobe (no Fresnel factor; see src/scene/brdf.rs).
        let base = Vec3::new(r, g, b);
        let metallic = pbr.metallic_factor().clamp(0.0, 1.0);
        let specular = Vec3::splat(0.04).lerp(base, metallic);
        self.materials.push(
            Material {
                emission,
                two_sided: material.double_sided(),
                albedo_texture,
                ..Material::diffuse(&name, base * (1.0 - metallic))
            }
            .with_gloss(
                specular.min(Vec3::ONE - base * (1.0 - metallic)),
                pbr.roughness_factor(),
            ),
        );
        let index = self.materials.len() as u32 - 1;
        if let Some(slot) = material.index().and_then(|i| self.material_of.get_mut(i)) {
            *slot = Some(index);
        }
        Ok((index, set))
    }

    /// glTF image `index` as an RGBA8 sRGB texture (converted once).
    fn texture(&mut self, index: usize) -> Result<Arc<Texture>, InputError> {
        if let Some(Some(texture)) = self.textures.get(index) {
            return Ok(texture.clone());
        }
        let image = self
            .images
            .get(index)
            .ok_or_else(|| self.error(format!("texture image {index} is missing")))?;
        let name = format!("{} image {index}", self.name);
        let texture = Arc::new(Texture::from_rgba8(
            &name,
            image.width,
            image.height,
            &rgba8(image),
        )?);
        self.textures[index] = Some(texture.clone());
        Ok(texture)
    }

    fn read_light(&mut self, light: &gltf::khr_lights_punctual::Light, world: Mat4) {
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z);
        let kind = match light.kind() {
            Kind::Directional => {
                self.warn(
                    "directional lights are ignored (vkgi has point, spot and area lights)".into(),
                );
                return;
            }
            Kind::Point => LightKind::Point,
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => LightKind::Spot {
                direction,
                cone_angle_deg: outer_cone_angle.to_degrees(),
                penumbra_deg: (outer_cone_angle - inner_cone_angle.min(outer_cone_angle))
                    .to_degrees(),
            },
        };
        if light.range().is_some() {
            self.warn(
                "light ranges are ignored (light falls off by the inverse square law)".into(),
            );
        }
        let unit = Light {
            position,
            kind,
            flux: 1.0,
            color: Vec3::ONE,
        };
        // glTF gives the peak intensity in candela; vkgi a flux spread over the profile.
        let watts_per_sr = light.intensity() / LUMENS_PER_WATT;
        self.lights.push(Light {
            flux: watts_per_sr * unit.profile_solid_angle(),
            color: Vec3::from(light.color()),
            ..unit
        });
    }

    fn read_camera(&mut self, camera: &gltf::Camera, world: Mat4) {
        match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let position = world.transform_point3(Vec3::ZERO);
                self.camera = Some(Camera {
                    position,
                    target: position + world.transform_vector3(Vec3::NEG_Z),
                    up: world.transform_vector3(Vec3::Y),
                    vfov_deg: p.yfov().to_degrees(),
                });
            }
            gltf::camera::Projection::Orthographic(_) => {
                self.warn("orthographic cameras are ignored".into());
            }
        }
    }
}

/// A glTF image's pixels as RGBA8 bytes: 8-bit channels as stored, 16-bit ones by their high
/// byte, float (linear) ones sRGB-encoded; grey and grey-alpha images spread to RGB.
fn rgba8(image: &gltf::image::Data) -> Vec<u8> {
    use gltf::image::Format;
    let (channels, bytes) = match image.format {
        Format::R8 => (1, 1),
        Format::R8G8 => (2, 1),
        Format::R8G8B8 => (3, 1),
        Format::R8G8B8A8 => (4, 1),
        Format::R16 => (1, 2),
        Format::R16G16 => (2, 2),
        Format::R16G16B16 => (3, 2),
        Format::R16G16B16A16 => (4, 2),
        Format::R32G32B32FLOAT => (3, 4),
        Format::R32G32B32A32FLOAT => (4, 4),
    };
    let channel = |p: &[u8], c: usize| -> u8 {
        let at = &p[c * bytes..(c + 1) * bytes];
        match bytes {
            1 => at[0],
            2 => (u16::from_ne_bytes([at[0], at[1]]) >> 8) as u8,
            _ => {
                let v = f32::from_ne_bytes([at[0], at[1], at[2], at[3]]);
                (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0).round() as u8
            }
        }
    };
    image
        .pixels
        .chunks_exact(channels * bytes)
        .flat_map(|p| {
            let grey = channels < 3;
            let r = channel(p, 0);
            let g = if grey { r } else { channel(p, 1) };
            let b = if grey { r } else { channel(p, 2) };
            [r, g, b, 255]
        })
        .collect()
}
