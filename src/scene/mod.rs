//! Scenes: triangle meshes with Lambertian materials (OBJ + MTL through tobj), punctual lights
//! and a camera, from a built-in name, a scene file (TOML) or a bare OBJ.

pub mod brdf;
pub mod builtin;
pub mod bvh;
pub mod camera;
pub mod dynamic;
pub mod emitters;
pub mod export;
pub mod file;
pub mod generate;
mod gltf_guard;
pub mod gltf_scene;
pub mod gpu;
pub mod intersect;
pub mod light;
pub mod movable;
pub mod obj;
pub mod texture;

use std::path::Path;
use std::sync::Arc;

use glam::{BVec3, Vec2, Vec3};

pub use camera::Camera;
pub use light::{Light, LightKind};
pub use texture::Texture;

use crate::error::InputError;

/// A material: diffuse albedo in [0, 1] (times its texture, if any), an optional glossy lobe
/// ([`brdf`]) and emitted radiance (W/(m²·sr)), emitted from the front face (by winding) only,
/// unless `two_sided`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub albedo: Vec3,
    pub emission: Vec3,
    /// Emit from both faces (e.g. glTF's doubleSided); surfaces reflect from both either way.
    pub two_sided: bool,
    /// Multiplies `albedo`, sampled at the surface's texture coordinates (shared between
    /// materials that use the same image).
    pub albedo_texture: Option<Arc<Texture>>,
    /// Reflectance of the glossy lobe (zero: Lambertian only; albedo + specular ≤ 1 per
    /// channel); see [`brdf`].
    pub specular: Vec3,
    /// Perceptual roughness of the glossy lobe, in [`brdf::MIN_ROUGHNESS`, 1].
    pub roughness: f32,
}

impl Material {
    /// An untextured diffuse material that does not emit.
    pub fn diffuse(name: &str, albedo: Vec3) -> Material {
        Material {
            name: name.to_string(),
            albedo,
            emission: Vec3::ZERO,
            two_sided: false,
            albedo_texture: None,
            specular: Vec3::ZERO,
            roughness: 1.0,
        }
    }

    /// This material with a glossy lobe of reflectance `specular` and `roughness` (clamped to
    /// the range [`brdf`] renders; NaN gives 1). [`Scene::new`] rejects a reflectance that is
    /// negative, not finite, or more than 1 with the albedo.
    pub fn with_gloss(self, specular: Vec3, roughness: f32) -> Material {
        let roughness = if roughness.is_nan() { 1.0 } else { roughness };
        Material {
            specular,
            roughness: roughness.clamp(brdf::MIN_ROUGHNESS, 1.0),
            ..self
        }
    }

    /// Whether the glossy lobe is more than a rough dielectric's 4%, the lobe glTF gives every
    /// non-metal (what `radiance-volumes --specular auto` looks for).
    pub fn is_visibly_glossy(&self) -> bool {
        let most = self.specular.max_element();
        most > 0.04 + 1e-6 || (most > 0.0 && self.roughness < 0.9)
    }

    /// The albedo at texture coordinates `uv`.
    pub fn albedo_at(&self, uv: Vec2) -> Vec3 {
        match &self.albedo_texture {
            Some(texture) => self.albedo * texture.sample(uv),
            None => self.albedo,
        }
    }
}

/// An indexed triangle mesh: unique vertices (position and shading normal) and three vertex
/// indices per triangle, each triangle with its material.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Unit shading normal per vertex, or zero where the file gives none: the triangle's face
    /// normal is used there (the shaders and the CPU estimators share this rule).
    pub normals: Vec<Vec3>,
    /// Texture coordinates per vertex (zero where the file gives none).
    pub texcoords: Vec<Vec2>,
    /// Vertex indices of each triangle, in winding order.
    pub indices: Vec<[u32; 3]>,
    /// Material index per triangle.
    pub materials: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        self.indices[t].map(|i| self.positions[i as usize])
    }

    /// Unit geometric normal of triangle `t` (by winding; shading flips it toward the viewer).
    pub fn face_normal(&self, t: usize) -> Vec3 {
        let [a, b, c] = self.triangle(t);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The shading normal at barycentric `(u, v)` of triangle `t`: the interpolated vertex
    /// normals, or the face normal where they vanish (vertices without normals).
    pub fn shading_normal(&self, t: usize, (u, v): (f32, f32)) -> Vec3 {
        let [a, b, c] = self.indices[t].map(|i| self.normals[i as usize]);
        let n = a * (1.0 - u - v) + b * u + c * v;
        if n.length_squared() > 1e-12 {
            n.normalize()
        } else {
            self.face_normal(t)
        }
    }

    /// Texture coordinates at barycentric `(u, v)` of triangle `t`.
    pub fn texcoord(&self, t: usize, (u, v): (f32, f32)) -> Vec2 {
        let [a, b, c] = self.indices[t].map(|i| self.texcoords[i as usize]);
        a * (1.0 - u - v) + b * u + c * v
    }

    /// Append a triangle with its own three vertices (normals zero: flat; texture
    /// coordinates zero).
    pub fn push_triangle(&mut self, corners: [Vec3; 3], normals: [Vec3; 3], material: u32) {
        let first = self.positions.len() as u32;
        self.positions.extend(corners);
        self.normals.extend(normals);
        self.texcoords.extend([Vec2::ZERO; 3]);
        self.indices.push([first, first + 1, first + 2]);
        self.materials.push(material);
    }

    /// Append the six faces of the axis-aligned box `min`..`max` (two triangles each, flat,
    /// wound outward).
    pub fn push_cuboid(&mut self, min: Vec3, max: Vec3, material: u32) {
        let corner =
            |i: usize| Vec3::select(BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), max, min);
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for face in faces {
            for tri in [[0, 1, 2], [0, 2, 3]] {
                self.push_triangle(tri.map(|k| corner(face[k])), [Vec3::ZERO; 3], material);
            }
        }
    }

    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub mesh: Mesh,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    pub bounds_min: Vec3,
    pub bounds_max: Vec3,
    /// Cosine-lobed lights the rasteriser and RSM-based methods sample the emissive triangles
    /// with (the path tracer samples the triangles themselves).
    pub area_samples: u32,
    /// Objects that move while the scene renders (see [`dynamic`]).
    pub dynamic: Vec<dynamic::DynamicObject>,
}

/// Area-light samples for rasterisation unless `--area-samples` says otherwise.
pub const DEFAULT_AREA_SAMPLES: u32 = 16;

impl Scene {
    /// Load a scene: a built-in name (`cornell`, `two-rooms`, the generated ones), a `.toml`
    /// scene file, a glTF 2.0 scene (`.gltf`, `.glb`), or a bare `.obj` (then a point light and
    /// camera are framed from its bounds).
    pub fn load(spec: &str) -> Result<Scene, InputError> {
        if let Some(scene) = builtin::load(spec)? {
            return Ok(scene);
        }
        let path = Path::new(spec);
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("toml") => file::load_scene_file(path),
            Some("gltf" | "glb") => gltf_scene::load(path),
            Some("obj") => {
                let obj::ObjMesh {
                    mesh, materials, ..
                } = obj::load(&obj::ObjSource::File(path), 1.0)?;
                let name = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "scene".into());
                Scene::framed(name, mesh, materials)
            }
            _ => Err(InputError::new(format!(
                "unknown scene '{spec}': expected a built-in name ({}), a .toml scene file, a glTF scene (.gltf, .glb) or an .obj mesh",
                builtin::names()
            ))),
        }
    }

    /// A scene around a bare mesh: camera from the front, a point light above and in front.
    pub fn framed(name: String, mesh: Mesh, materials: Vec<Material>) -> Result<Scene, InputError> {
        let (min, max) = check_mesh(&name, &mesh)?;
        let camera = Camera::framing(min, max);
        Scene::new(name, mesh, materials, vec![framing_light(min, max)], camera)
    }

    /// Assemble and validate a scene.
    pub fn new(
        name: String,
        mesh: Mesh,
        materials: Vec<Material>,
        lights: Vec<Light>,
        camera: Camera,
    ) -> Result<Scene, InputError> {
        if mesh.triangle_count() == 0 {
            return Err(InputError::new(format!(
                "scene '{name}': the mesh has no triangles"
            )));
        }
        let (bounds_min, bounds_max) = check_mesh(&name, &mesh)?;
        for m in &materials {
            let albedo_ok = m.albedo.is_finite()
                && m.albedo.min_element() >= 0.0
                && m.albedo.max_element() <= 1.0;
            let emission_ok = m.emission.is_finite()
                && m.emission.min_element() >= 0.0
                && m.emission.max_element() <= MAX_POWER;
            if !(albedo_ok && emission_ok) {
                return Err(InputError::new(format!(
                    "scene '{name}': material '{}' needs an albedo in [0, 1] and an emission in [0, {MAX_POWER:e}] per channel (it has {} and {})",
                    m.name, m.albedo, m.emission
                )));
            }
            let reflects = m.albedo + m.specular;
            let gloss_ok = m.specular.is_finite()
                && m.specular.min_element() >= 0.0
                && reflects.max_element() <= 1.0 + 1e-6
                && (brdf::MIN_ROUGHNESS..=1.0).contains(&m.roughness);
            if !gloss_ok {
                return Err(InputError::new(format!(
                    "scene '{name}': material '{}' needs a glossy reflectance >= 0 with albedo + reflectance <= 1 per channel and a roughness in [{}, 1] (it has {}, albedo {}, roughness {})",
                    m.name,
                    brdf::MIN_ROUGHNESS,
                    m.specular,
                    m.albedo,
                    m.roughness
                )));
            }
        }
        check_textures(&name, &mesh, &materials)?;
        let emissive = materials.iter().any(|m| m.emission.max_element() > 0.0);
        if lights.is_empty() && !emissive {
            return Err(InputError::new(format!(
                "scene '{name}' has no light: add a [[light]] (point, spot or area) to the scene file or an emissive (Ke) material"
            )));
        }
        let lights = lights
            .into_iter()
            .enumerate()
            .map(|(i, light)| validate_light(i, light))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|m| InputError::new(format!("scene '{name}': {m}")))?;
        let camera_ok = [camera.position, camera.target, camera.up]
            .iter()
            .all(|v| v.is_finite())
            && [camera.position, camera.target]
                .iter()
                .all(|v| v.abs().max_element() <= MAX_COORDINATE)
            && (camera.target - camera.position).length() > 0.0
            && camera.up.cross(camera.target - camera.position).length() > 0.0
            && camera.vfov_deg.is_finite()
            && camera.vfov_deg > 0.1
            && camera.vfov_deg < 179.0;
        if !camera_ok {
            return Err(InputError::new(format!(
                "scene '{name}': the camera needs a position and target within ±{MAX_COORDINATE:e}, \
                 a target away from the position, an up vector not along the view, and a field of \
                 view in (0.1, 179) degrees"
            )));
        }
        if !camera
            .view_projection(1.0, bounds_min, bounds_max)
            .is_finite()
        {
            return Err(InputError::new(format!(
                "scene '{name}': the camera's projection is not finite (the camera is too far from the scene for single-precision floats)"
            )));
        }
        Ok(Scene {
            name,
            mesh,
            materials,
            lights,
            camera,
            bounds_min,
            bounds_max,
            area_samples: DEFAULT_AREA_SAMPLES,
            dynamic: Vec::new(),
        })
    }

    /// The albedo at barycentric `(u, v)` of triangle `t` (textured where its material is).
    pub fn albedo(&self, t: usize, uv: (f32, f32)) -> Vec3 {
        let material = &self.materials[self.mesh.materials[t] as usize];
        match material.albedo_texture {
            Some(_) => material.albedo_at(self.mesh.texcoord(t, uv)),
            None => material.albedo,
        }
    }

    /// Whether any material has an albedo texture.
    pub fn textured(&self) -> bool {
        self.materials.iter().any(|m| m.albedo_texture.is_some())
    }

    /// The distinct albedo textures, in the order the GPU's texture table holds them, and each
    /// material's index into it.
    pub fn textures(&self) -> (Vec<&Arc<Texture>>, Vec<Option<u32>>) {
        let mut textures: Vec<&Arc<Texture>> = Vec::new();
        let indices = self
            .materials
            .iter()
            .map(|m| {
                m.albedo_texture.as_ref().map(|t| {
                    match textures.iter().position(|u| Arc::ptr_eq(u, t)) {
                        Some(i) => i as u32,
                        None => {
                            textures.push(t);
                            textures.len() as u32 - 1
                        }
                    }
                })
            })
            .collect();
        (textures, indices)
    }

    /// One line for `-v` and the profile: triangles, emitters, lights, bounds.
    pub fn statistics(&self) -> String {
        let emissive = (0..self.mesh.triangle_count())
            .filter(|&t| {
                self.materials[self.mesh.materials[t] as usize]
                    .emission
                    .max_element()
                    > 0.0
            })
            .count();
        let size = self.bounds_max - self.bounds_min;
        format!(
            "scene {}: {} triangles ({emissive} emissive, sampled by {} area-light samples for rasterisation), {} vertices, {} punctual light(s), bounds {:.4} .. {:.4} ({:.4} x {:.4} x {:.4})",
            self.name,
            self.mesh.triangle_count(),
            if emissive > 0 { self.area_samples } else { 0 },
            self.mesh.positions.len(),
            self.lights.len(),
            self.bounds_min,
            self.bounds_max,
            size.x,
            size.y,
            size.z
        )
    }

    /// The lights as the rasteriser and the RSM-based methods see them: the punctual lights,
    /// then `area_samples` cosine-lobed lights on the emissive triangles.
    pub fn raster_lights(&self) -> Vec<Light> {
        let offset = 1e-3 * (self.bounds_max - self.bounds_min).length();
        let mut lights = self.lights.clone();
        lights.extend(emitters::area_light_samples(
            self,
            self.area_samples,
            offset,
        ));
        lights
    }
}

/// A point light above and in front of the box `[min, max]`, about 3 W/m² at its centre (a
/// mid-grey exposure), for meshes that come without lights.
pub fn framing_light(min: Vec3, max: Vec3) -> Light {
    let radius = 0.5 * (max - min).length().max(1e-3);
    let center = 0.5 * (min + max);
    let position = center + Vec3::new(0.35, 1.2, 1.6) * radius;
    let distance = (position - center).length();
    Light {
        position,
        kind: LightKind::Point,
        flux: 3.0 * 4.0 * std::f32::consts::PI * distance * distance,
        color: Vec3::ONE,
    }
}

/// Largest coordinate magnitude, in scene units: squared lengths of edge cross products (face
/// normals, in f32 on the GPU) stay inside single-precision range: (2e9)^4 * 3 < 3.4e38.
pub const MAX_COORDINATE: f32 = 1e9;
/// Smallest extent of a mesh relative to its distance from the origin that single-precision
/// floats resolve to a useful degree (about 1700 steps across it).
const MIN_RELATIVE_EXTENT: f32 = 1e-4;
/// Largest power per channel of a light (W) or emitted radiance of a material: products with
/// geometry factors stay finite.
pub const MAX_POWER: f32 = 1e20;

/// Most triangles a mesh may have: the BVH's leaves index triangles in 27 bits.
pub const MAX_TRIANGLES: usize = (1 << (32 - bvh::LEAF_COUNT_BITS)) - 1;

fn check_triangle_count(name: &str, triangles: usize) -> Result<(), InputError> {
    if triangles > MAX_TRIANGLES {
        return Err(InputError::new(format!(
            "scene '{name}': the mesh has {triangles} triangles, over vkgi's limit of {MAX_TRIANGLES}"
        )));
    }
    Ok(())
}

/// The mesh's bounds, once its coordinates are known to be within what vkgi resolves.
fn check_mesh(name: &str, mesh: &Mesh) -> Result<(Vec3, Vec3), InputError> {
    check_triangle_count(name, mesh.triangle_count())?;
    let (min, max) = mesh.bounds();
    let reach = min.abs().max(max.abs()).max_element();
    if !(reach.is_finite() && reach <= MAX_COORDINATE) {
        return Err(InputError::new(format!(
            "scene '{name}': the mesh reaches coordinate {reach:e}, beyond vkgi's limit of ±{MAX_COORDINATE:e} scene units (rescale it)"
        )));
    }
    let extent = (max - min).max_element();
    if !(extent > 0.0 && extent >= MIN_RELATIVE_EXTENT * reach) {
        return Err(InputError::new(format!(
            "scene '{name}': the mesh is {extent:e} units across at {reach:e} from the origin; single-precision floats cannot resolve it there (move it toward the origin)"
        )));
    }
    Ok((min, max))
}

/// Texture coordinates for every vertex, finite, and textures within vkgi's memory limit.
fn check_textures(name: &str, mesh: &Mesh, materials: &[Material]) -> Result<(), InputError> {
    if mesh.texcoords.len() != mesh.positions.len() {
        return Err(InputError::new(format!(
            "scene '{name}': {} texture coordinates for {} vertices",
            mesh.texcoords.len(),
            mesh.positions.len()
        )));
    }
    if let Some(v) = mesh.texcoords.iter().position(|t| !t.is_finite()) {
        return Err(InputError::new(format!(
            "scene '{name}': vertex {} has non-finite texture coordinates",
            v + 1
        )));
    }
    let mut seen: Vec<&Arc<Texture>> = Vec::new();
    let mut texels = 0u64;
    for t in materials.iter().filter_map(|m| m.albedo_texture.as_ref()) {
        if !seen.iter().any(|s| Arc::ptr_eq(s, t)) {
            seen.push(t);
            texels += u64::from(t.width) * u64::from(t.height);
        }
    }
    if texels > texture::MAX_SCENE_TEXELS {
        return Err(InputError::new(format!(
            "scene '{name}': its textures hold {texels} texels, over vkgi's limit of {}",
            texture::MAX_SCENE_TEXELS
        )));
    }
    Ok(())
}

/// Check a light and return it with a unit spot direction (normalised in f64, so a long
/// direction vector does not overflow).
fn validate_light(index: usize, mut light: Light) -> Result<Light, String> {
    let what = format!("light {}", index + 1);
    if !(light.position.is_finite() && light.position.abs().max_element() <= MAX_COORDINATE) {
        return Err(format!(
            "{what}: position must be finite and within ±{MAX_COORDINATE:e}"
        ));
    }
    if !(light.flux.is_finite() && light.flux >= 0.0) {
        return Err(format!(
            "{what}: flux must be a finite number of watts >= 0"
        ));
    }
    if !(light.color.is_finite() && light.color.min_element() >= 0.0) {
        return Err(format!("{what}: color components must be finite and >= 0"));
    }
    let power = f64::from(light.flux) * f64::from(light.color.max_element());
    if power > f64::from(MAX_POWER) {
        return Err(format!(
            "{what}: flux × color is {power:e} W in one channel, over vkgi's limit of {MAX_POWER:e} W"
        ));
    }
    if let LightKind::Spot {
        direction,
        cone_angle_deg,
        penumbra_deg,
    } = &mut light.kind
    {
        let unit = direction.as_dvec3().normalize_or_zero().as_vec3();
        if !(direction.is_finite() && unit.is_finite() && unit.length() > 0.5) {
            return Err(format!(
                "{what}: direction must be a finite, non-zero vector"
            ));
        }
        *direction = unit;
        if !(cone_angle_deg.is_finite()
            && *cone_angle_deg >= light::MIN_CONE_DEG
            && *cone_angle_deg <= light::MAX_CONE_DEG)
        {
            return Err(format!(
                "{what}: cone_angle is the half-angle of the cone and must be in [{}, {}] degrees",
                light::MIN_CONE_DEG,
                light::MAX_CONE_DEG
            ));
        }
        if !(penumbra_deg.is_finite() && (0.0..=*cone_angle_deg).contains(penumbra_deg)) {
            return Err(format!(
                "{what}: penumbra must be in [0, cone_angle] degrees"
            ));
        }
    }
    Ok(light)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(a: Vec3, b: Vec3, c: Vec3) -> Mesh {
        let mut mesh = Mesh::default();
        mesh.push_triangle([a, b, c], [Vec3::ZERO; 3], 0);
        mesh
    }

    fn material() -> Vec<Material> {
        vec![Material::diffuse("m", Vec3::splat(0.5))]
    }

    fn point(position: Vec3, flux: f32, color: Vec3) -> Light {
        Light {
            position,
            kind: LightKind::Point,
            flux,
            color,
        }
    }

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 40.0,
        }
    }

    fn unit() -> Mesh {
        triangle(Vec3::ZERO, Vec3::X, Vec3::Y)
    }

    #[test]
    fn light_power_is_checked_as_a_product() {
        let scene = |flux: f32, color: Vec3| {
            Scene::new(
                "s".into(),
                unit(),
                material(),
                vec![point(Vec3::Z, flux, color)],
                camera(),
            )
        };
        assert!(scene(10.0, Vec3::ONE).is_ok());
        let err = scene(3e38, Vec3::ONE).unwrap_err();
        assert!(err.0.contains("limit"), "{err}");
        assert!(scene(1.0, Vec3::new(1e38, 1.0, 1.0)).is_err());
        assert!(
            scene(0.0, Vec3::ONE).is_ok(),
            "zero flux is a valid (dark) light"
        );
    }

    #[test]
    fn a_huge_spot_direction_is_normalised_in_double_precision() {
        let spot = Light {
            position: Vec3::Z,
            kind: LightKind::Spot {
                direction: Vec3::new(1e38, 0.0, 0.0),
                cone_angle_deg: 30.0,
                penumbra_deg: 5.0,
            },
            flux: 1.0,
            color: Vec3::ONE,
        };
        let scene = Scene::new("s".into(), unit(), material(), vec![spot], camera()).unwrap();
        let LightKind::Spot { direction, .. } = scene.lights[0].kind else {
            panic!("a spot light")
        };
        assert_eq!(direction, Vec3::X);
    }

    #[test]
    fn coordinates_far_beyond_the_scene_are_rejected() {
        let far = Vec3::splat(1e37);
        let light_far = Scene::new(
            "s".into(),
            unit(),
            material(),
            vec![point(far, 1.0, Vec3::ONE)],
            camera(),
        );
        assert!(light_far.unwrap_err().0.contains("light 1"));
        let camera_far = Camera {
            position: far,
            ..camera()
        };
        let lights = vec![point(Vec3::Z, 1.0, Vec3::ONE)];
        assert!(Scene::new("s".into(), unit(), material(), lights.clone(), camera_far).is_err());
        let huge = triangle(Vec3::ZERO, Vec3::X * 1e30, Vec3::Y * 1e30);
        let err = Scene::framed("s".into(), huge, material()).unwrap_err();
        assert!(err.0.contains("the mesh reaches coordinate"), "{err}");
        let tiny_far = triangle(
            Vec3::splat(1e8),
            Vec3::splat(1e8) + Vec3::X * 100.0,
            Vec3::splat(1e8) + Vec3::Y * 100.0,
        );
        let err = Scene::framed("s".into(), tiny_far, material()).unwrap_err();
        assert!(err.0.contains("cannot resolve"), "{err}");
    }

    #[test]
    fn a_cuboid_is_closed_and_wound_outward() {
        let mut mesh = Mesh::default();
        let (min, max) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 2.5));
        mesh.push_cuboid(min, max, 0);
        assert_eq!(mesh.triangle_count(), 12);
        let centre = 0.5 * (min + max);
        let mut area = 0.0;
        for t in 0..12 {
            let [a, b, c] = mesh.triangle(t);
            let n = (b - a).cross(c - a);
            assert!(
                n.dot((a + b + c) / 3.0 - centre) > 0.0,
                "triangle {t} faces inward"
            );
            area += 0.5 * n.length();
        }
        let e = max - min;
        assert!((area - 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)).abs() < 1e-5);
    }

    #[test]
    fn the_bvh_triangle_limit_is_checked() {
        assert!(check_triangle_count("s", MAX_TRIANGLES).is_ok());
        let err = check_triangle_count("s", MAX_TRIANGLES + 1).unwrap_err();
        assert!(err.0.contains("134217727"), "{err}");
    }

    #[test]
    fn emission_and_albedo_are_range_checked() {
        let mut hot = material();
        hot[0].emission = Vec3::splat(1e38);
        assert!(Scene::new("s".into(), unit(), hot, vec![], camera()).is_err());
    }
}
