//! Scene files (TOML): the mesh, a scale, the camera and the lights.
//!
//! ```toml
//! mesh = "../cornell-box.obj"   # relative to this file
//! scale = 0.001                 # file units to metres (applies to mesh, camera and lights)
//! [camera]
//! position = [278, 273, -800]
//! target = [278, 273, 0]
//! up = [0, 1, 0]                # optional
//! fov = 39.3                    # vertical, degrees
//! [[light]]
//! type = "spot"                 # or "point" (no direction, cone_angle, penumbra)
//! position = [278, 530, 230]
//! direction = [0, -1, 0]
//! cone_angle = 60               # half-angle of the cone, degrees
//! penumbra = 8                  # soft edge inside the cone, degrees
//! flux = 5                      # watts
//! color = [1, 1, 1]             # optional per-channel tint of the flux
//! [[light]]
//! type = "area"                 # a rectangle of emissive triangles
//! center = [278, 548, 280]
//! edges = [[130, 0, 0], [0, 0, 105]]  # front face along edges[0] × edges[1]
//! radiance = 40                 # W/(m²·sr), or flux = … (watts leaving it); one of the two
//! color = [1, 1, 1]             # optional tint
//! two_sided = false             # optional: emit from the back face too
//! [[dynamic]]                   # an object that moves while the scene renders
//! object = "tall_block"         # an OBJ object (o) or group (g) of the mesh, or instead:
//! # box = [[0, 0, 0], [100, 100, 100]]  # a closed box (min, max corners) the file adds
//! # albedo = [0.8, 0.8, 0.8]    # the box's albedo (default 0.8 grey)
//! # name = "door"               # optional (default: the object's name, or box-N)
//! path = [{ frame = 0, offset = [0, 0, 0] }, { frame = 60, offset = [-150, 0, 0] }]
//! loop = false                  # optional: repeat the path after its last keyframe
//! ```
//!
//! A path's offsets move the object from where the mesh puts it (file units, scaled), linearly
//! between keyframes; before the first keyframe it is at the first offset, after the last at
//! the last (or, looped, the path starts again).

use std::ops::Range;
use std::path::Path;

use glam::Vec3;
use serde::{Deserialize, Deserializer};

use super::dynamic;
use super::obj::{self, ObjMesh, ObjSource};
use super::{Camera, Light, LightKind, Material, Mesh, Scene};
use crate::error::InputError;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub mesh: String,
    #[serde(default = "unit_scale")]
    pub scale: f32,
    pub camera: Option<CameraFile>,
    #[serde(default, rename = "light")]
    pub lights: Vec<LightFile>,
    #[serde(default)]
    pub dynamic: Vec<DynamicFile>,
}

/// An object that moves by a path (see the module's example).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicFile {
    object: Option<String>,
    #[serde(rename = "box", default, deserialize_with = "optional_two_vectors")]
    cuboid: Option<[[f32; 3]; 2]>,
    #[serde(default, deserialize_with = "optional_three")]
    albedo: Option<[f32; 3]>,
    name: Option<String>,
    path: Vec<KeyframeFile>,
    #[serde(default, rename = "loop")]
    looped: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KeyframeFile {
    frame: u64,
    #[serde(deserialize_with = "three")]
    offset: [f32; 3],
}

/// Albedo of a dynamic box without one.
const DEFAULT_BOX_ALBEDO: f32 = 0.8;

fn unit_scale() -> f32 {
    1.0
}

/// An `[x, y, z]` array of exactly three numbers (serde's fixed arrays let a fourth through).
fn three<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
    let values = Vec::<f32>::deserialize(d)?;
    <[f32; 3]>::try_from(values.as_slice()).map_err(|_| {
        serde::de::Error::custom(format!(
            "expected 3 numbers [x, y, z], found {}",
            values.len()
        ))
    })
}

fn optional_three<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    three(d).map(Some)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    #[serde(deserialize_with = "three")]
    pub position: [f32; 3],
    #[serde(deserialize_with = "three")]
    pub target: [f32; 3],
    #[serde(default, deserialize_with = "optional_three")]
    pub up: Option<[f32; 3]>,
    pub fov: f32,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum LightFile {
    Spot {
        #[serde(deserialize_with = "three")]
        position: [f32; 3],
        #[serde(deserialize_with = "three")]
        direction: [f32; 3],
        cone_angle: f32,
        penumbra: f32,
        flux: f32,
        #[serde(default, deserialize_with = "optional_three")]
        color: Option<[f32; 3]>,
    },
    Point {
        #[serde(deserialize_with = "three")]
        position: [f32; 3],
        flux: f32,
        #[serde(default, deserialize_with = "optional_three")]
        color: Option<[f32; 3]>,
    },
    Area(AreaLightFile),
}

/// A rectangular area light: emissive triangles appended to the mesh.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AreaLightFile {
    #[serde(deserialize_with = "three")]
    center: [f32; 3],
    /// Two edge vectors of the rectangle; its front face is along `edges[0] × edges[1]`.
    #[serde(deserialize_with = "two_vectors")]
    edges: [[f32; 3]; 2],
    /// Emitted radiance, W/(m²·sr) (scene units are metres after `scale`).
    radiance: Option<f32>,
    /// Flux leaving the light, watts (instead of `radiance`).
    flux: Option<f32>,
    #[serde(default, deserialize_with = "optional_three")]
    color: Option<[f32; 3]>,
    #[serde(default)]
    two_sided: bool,
}

fn optional_two_vectors<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[[f32; 3]; 2]>, D::Error> {
    two_vectors(d).map(Some)
}

fn two_vectors<'de, D: Deserializer<'de>>(d: D) -> Result<[[f32; 3]; 2], D::Error> {
    let values = Vec::<Vec<f32>>::deserialize(d)?;
    let vectors: Option<Vec<[f32; 3]>> = values
        .iter()
        .map(|v| <[f32; 3]>::try_from(v.as_slice()).ok())
        .collect();
    vectors
        .and_then(|v| <[[f32; 3]; 2]>::try_from(v).ok())
        .ok_or_else(|| serde::de::Error::custom("expected two vectors [[x, y, z], [x, y, z]]"))
}

impl AreaLightFile {
    /// The rectangle's corners (front face by winding) and its emitted radiance per channel,
    /// after scaling by `scale`; `index` names the light in errors.
    fn emitter(&self, scale: f32, index: usize) -> Result<([Vec3; 4], Vec3, bool), String> {
        let what = format!("light {} (area)", index + 1);
        let center = Vec3::from(self.center) * scale;
        let [e0, e1] = self.edges.map(|e| Vec3::from(e) * scale);
        let normal = e0.as_dvec3().cross(e1.as_dvec3());
        let area = normal.length();
        if !(center.is_finite() && e0.is_finite() && e1.is_finite() && area.is_finite()) {
            return Err(format!("{what}: center and edges must be finite"));
        }
        if area
            <= 1e-12
                * e0.as_dvec3()
                    .length_squared()
                    .max(e1.as_dvec3().length_squared())
        {
            return Err(format!(
                "{what}: the edges are parallel or zero; the rectangle has no area"
            ));
        }
        let color = Vec3::from(self.color.unwrap_or([1.0; 3]));
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let radiance = match (self.radiance, self.flux) {
            (Some(l), None) => f64::from(l),
            // Φ = π L A per emitting side of a Lambertian emitter.
            (None, Some(flux)) => f64::from(flux) / (std::f64::consts::PI * area * sides),
            _ => {
                return Err(format!(
                    "{what}: give exactly one of radiance (W/(m²·sr)) or flux (W)"
                ));
            }
        };
        if !(radiance.is_finite() && radiance >= 0.0) {
            return Err(format!(
                "{what}: radiance and flux must be finite numbers >= 0"
            ));
        }
        let corner = |a: f32, b: f32| center + 0.5 * (a * e0 + b * e1);
        let corners = [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        Ok((corners, radiance as f32 * color, self.two_sided))
    }
}

impl SceneFile {
    pub fn parse(text: &str, origin: &str) -> Result<SceneFile, InputError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let message = e.message().to_string();
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].lines().count().max(1));
            match line {
                Some(line) => {
                    InputError::new(format!("{origin}:{line}: malformed scene file: {message}"))
                }
                None => InputError::new(format!("{origin}: malformed scene file: {message}")),
            }
        })?;
        if !(file.scale.is_finite() && file.scale > 0.0) {
            return Err(InputError::new(format!(
                "{origin}: scale must be a finite number > 0"
            )));
        }
        Ok(file)
    }

    /// Build the scene around an already-loaded mesh (in file units, scaled by the caller).
    pub fn into_scene(self, name: String, obj: ObjMesh) -> Result<Scene, InputError> {
        let ObjMesh {
            mut mesh,
            mut materials,
            objects,
        } = obj;
        let mut dynamic = Vec::new();
        for (index, d) in self.dynamic.iter().enumerate() {
            let (object_name, triangles) = d
                .triangles(index, &objects, &mut mesh, &mut materials, self.scale)
                .map_err(|m| InputError::new(format!("scene '{name}': {m}")))?;
            dynamic.push((object_name, triangles, d.path(index, self.scale)));
        }
        let s = self.scale;
        let v = |a: [f32; 3]| Vec3::from(a) * s;
        for (index, light) in self.lights.iter().enumerate() {
            if let LightFile::Area(area) = light {
                let (corners, emission, two_sided) = area
                    .emitter(s, index)
                    .map_err(|m| InputError::new(format!("scene '{name}': {m}")))?;
                append_emitter(
                    &mut mesh,
                    &mut materials,
                    index,
                    corners,
                    emission,
                    two_sided,
                );
            }
        }
        let lights = self
            .lights
            .iter()
            .filter_map(|l| match *l {
                LightFile::Spot {
                    position,
                    direction,
                    cone_angle,
                    penumbra,
                    flux,
                    color,
                } => Some(Light {
                    position: v(position),
                    kind: LightKind::Spot {
                        direction: Vec3::from(direction),
                        cone_angle_deg: cone_angle,
                        penumbra_deg: penumbra,
                    },
                    flux,
                    color: Vec3::from(color.unwrap_or([1.0; 3])),
                }),
                LightFile::Point {
                    position,
                    flux,
                    color,
                } => Some(Light {
                    position: v(position),
                    kind: LightKind::Point,
                    flux,
                    color: Vec3::from(color.unwrap_or([1.0; 3])),
                }),
                LightFile::Area(_) => None,
            })
            .collect();
        let camera = match &self.camera {
            Some(c) => Camera {
                position: v(c.position),
                target: v(c.target),
                up: Vec3::from(c.up.unwrap_or([0.0, 1.0, 0.0])),
                vfov_deg: c.fov,
            },
            None => {
                let (min, max) = mesh.bounds();
                Camera::framing(min, max)
            }
        };
        let mut scene = Scene::new(name, mesh, materials, lights, camera)?;
        for (object_name, triangles, path) in dynamic {
            let path = path.map_err(|m| InputError::new(format!("scene '{}': {m}", scene.name)))?;
            scene.add_dynamic(&object_name, &triangles, path)?;
        }
        Ok(scene)
    }
}

impl DynamicFile {
    /// The name and triangles of dynamic object `index`: an object or group of the OBJ, or a
    /// box appended to the mesh with a material of its own.
    fn triangles(
        &self,
        index: usize,
        objects: &[(String, Range<usize>)],
        mesh: &mut Mesh,
        materials: &mut Vec<Material>,
        scale: f32,
    ) -> Result<(String, Vec<usize>), String> {
        let what = format!("dynamic object {}", index + 1);
        match (&self.object, &self.cuboid) {
            (Some(object), None) => {
                if self.albedo.is_some() {
                    return Err(format!(
                        "{what}: albedo is for a box (an object keeps its materials)"
                    ));
                }
                let triangles = obj::triangles_of(objects, object);
                if triangles.is_empty() {
                    return Err(format!(
                        "{what}: the mesh has no object or group '{object}' with triangles"
                    ));
                }
                Ok((
                    self.name.clone().unwrap_or_else(|| object.clone()),
                    triangles,
                ))
            }
            (None, Some([min, max])) => {
                let (min, max) = (Vec3::from(*min) * scale, Vec3::from(*max) * scale);
                if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
                    return Err(format!(
                        "{what}: a box needs finite corners with min < max on every axis"
                    ));
                }
                let albedo = Vec3::from(self.albedo.unwrap_or([DEFAULT_BOX_ALBEDO; 3]));
                let name = self
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("box-{}", index + 1));
                let material = materials.len() as u32;
                materials.push(Material::diffuse(&name, albedo));
                let first = mesh.triangle_count();
                mesh.push_cuboid(min, max, material);
                Ok((name, (first..mesh.triangle_count()).collect()))
            }
            _ => Err(format!(
                "{what}: give exactly one of object = \"NAME\" or box = [[min], [max]]"
            )),
        }
    }

    /// The path of dynamic object `index`, its offsets scaled.
    fn path(&self, index: usize, scale: f32) -> Result<dynamic::Path, String> {
        let keys = self
            .path
            .iter()
            .map(|k| (k.frame, Vec3::from(k.offset) * scale))
            .collect();
        dynamic::Path::new(keys, self.looped)
            .map_err(|m| format!("dynamic object {}: {m}", index + 1))
    }
}

/// Append an area light's rectangle to the mesh as two emissive triangles with a black,
/// emitting material of its own.
fn append_emitter(
    mesh: &mut super::Mesh,
    materials: &mut Vec<super::Material>,
    index: usize,
    [a, b, c, d]: [Vec3; 4],
    emission: Vec3,
    two_sided: bool,
) {
    let material = materials.len() as u32;
    materials.push(super::Material {
        emission,
        two_sided,
        ..super::Material::diffuse(&format!("area-light-{}", index + 1), Vec3::ZERO)
    });
    mesh.push_triangle([a, b, c], [Vec3::ZERO; 3], material);
    mesh.push_triangle([a, c, d], [Vec3::ZERO; 3], material);
}

/// Load a scene whose scene file, OBJ and MTL are texts in memory (built-in scenes, fuzzing);
/// the scene file's `mesh` entry is not read.
pub fn load_embedded(
    name: &str,
    scene_file: &str,
    obj: &str,
    mtl: &str,
) -> Result<Scene, InputError> {
    let file = SceneFile::parse(scene_file, name)?;
    let source = ObjSource::Embedded { name, obj, mtl };
    let loaded = obj::load(&source, file.scale)?;
    file.into_scene(name.to_string(), loaded)
}

/// Load a scene file from disk; its mesh path is relative to the file.
pub fn load_scene_file(path: &Path) -> Result<Scene, InputError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new(format!("{origin}: cannot read scene file: {e}")))?;
    let file = SceneFile::parse(&text, &origin)?;
    let mesh_path = path.parent().unwrap_or(Path::new(".")).join(&file.mesh);
    let loaded = obj::load(&ObjSource::File(&mesh_path), file.scale)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    file.into_scene(name, loaded)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn malformed_toml_names_the_line() {
        let err = SceneFile::parse("mesh = \"a.obj\"\n[camera]\nposition = [1, 2\n", "s.toml")
            .err()
            .unwrap();
        assert!(err.to_string().starts_with("s.toml:"), "{err}");
    }

    #[test]
    fn unknown_keys_and_light_types_are_rejected() {
        assert!(SceneFile::parse("mesh = \"a.obj\"\nsclae = 2\n", "s").is_err());
        let area = "mesh = \"a.obj\"\n[[light]]\ntype = \"area\"\nposition = [0,0,0]\nflux = 1\n";
        assert!(SceneFile::parse(area, "s").is_err());
        assert!(SceneFile::parse("mesh = \"a.obj\"\n[[light]]\ntype = \"disc\"\n", "s").is_err());
        assert!(SceneFile::parse("mesh = \"a.obj\"\nscale = -1\n", "s").is_err());
    }

    #[test]
    fn vectors_must_have_exactly_three_numbers() {
        let camera = |position: &str| {
            format!(
                "mesh = \"a.obj\"\n[camera]\nposition = {position}\ntarget = [0,0,0]\nfov = 40\n"
            )
        };
        assert!(SceneFile::parse(&camera("[1, 2, 3]"), "s").is_ok());
        for bad in ["[1, 2, 3, 4]", "[1, 2]", "[]", "\"up\""] {
            let err = SceneFile::parse(&camera(bad), "s").err().unwrap();
            assert!(err.to_string().contains("s:"), "{bad}: {err}");
        }
        let colour = "mesh = \"a.obj\"\n[[light]]\ntype = \"point\"\nposition = [0,1,0]\nflux = 2\ncolor = [1,1,1,1]\n";
        assert!(SceneFile::parse(colour, "s").is_err());
    }

    #[test]
    fn lights_parse_with_defaults() {
        let text = "mesh = \"a.obj\"\n[[light]]\ntype = \"point\"\nposition = [0,1,0]\nflux = 2\n";
        let file = SceneFile::parse(text, "s").unwrap();
        assert_eq!(file.lights.len(), 1);
        assert_eq!(file.scale, 1.0);
    }

    /// A floor triangle, as the OBJ object "floor".
    fn floor() -> ObjMesh {
        let mut mesh = Mesh::default();
        let corners = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0)];
        mesh.push_triangle(corners, [Vec3::ZERO; 3], 0);
        let material = Material::diffuse("floor", Vec3::splat(0.5));
        ObjMesh {
            mesh,
            materials: vec![material],
            objects: vec![("floor".into(), 0..1)],
        }
    }

    fn area_scene(light: &str) -> Result<Scene, InputError> {
        let text = format!("mesh = \"a.obj\"\nscale = 0.5\n[[light]]\ntype = \"area\"\n{light}");
        SceneFile::parse(&text, "s")?.into_scene("s".into(), floor())
    }

    fn dynamic_scene(dynamic: &str) -> Result<Scene, InputError> {
        let text = format!(
            "mesh = \"a.obj\"\nscale = 0.5\n[[light]]\ntype = \"point\"\nposition = [0, 2, 0]\nflux = 1\n[[dynamic]]\n{dynamic}"
        );
        SceneFile::parse(&text, "s")?.into_scene("s".into(), floor())
    }

    #[test]
    fn dynamic_objects_are_named_objects_or_added_boxes_with_scaled_paths() {
        let object = dynamic_scene(
            "object = \"floor\"\npath = [{ frame = 0, offset = [0, 0, 0] }, { frame = 10, offset = [2, 0, 0] }]\n",
        )
        .unwrap();
        assert_eq!(object.dynamic.len(), 1);
        assert_eq!(object.dynamic[0].name, "floor");
        assert_eq!(
            object.dynamic[0].path.at(5),
            Vec3::new(0.5, 0.0, 0.0),
            "scaled"
        );
        assert!(
            (object.bounds_max.x - 2.0).abs() < 1e-6,
            "bounds take in the path"
        );
        let cube = dynamic_scene(
            "box = [[0, 0, 0], [1, 1, 1]]\nalbedo = [0.2, 0.3, 0.4]\nname = \"door\"\nloop = true\npath = [{ frame = 0, offset = [0, 0, 0] }, { frame = 4, offset = [0, 2, 0] }]\n",
        )
        .unwrap();
        let door = &cube.dynamic[0];
        assert_eq!((door.name.as_str(), door.vertices.len()), ("door", 36));
        assert_eq!(
            door.path.at(6),
            Vec3::new(0.0, 0.5, 0.0),
            "looped and scaled"
        );
        assert_eq!(cube.materials[1].albedo, Vec3::new(0.2, 0.3, 0.4));
        assert_eq!(cube.mesh.triangle_count(), 13);
    }

    #[test]
    fn bad_dynamic_objects_are_one_line_errors() {
        let still = "path = [{ frame = 0, offset = [0, 0, 0] }]\n";
        let errors = [
            format!("object = \"wall\"\n{still}"),
            format!("object = \"floor\"\nbox = [[0, 0, 0], [1, 1, 1]]\n{still}"),
            still.to_string(),
            format!("box = [[0, 0, 0], [1, 0, 1]]\n{still}"),
            format!("object = \"floor\"\nalbedo = [1, 1, 1]\n{still}"),
            "object = \"floor\"\npath = []\n".into(),
            "object = \"floor\"\npath = [{ frame = 2, offset = [0, 0, 0] }, { frame = 1, offset = [0, 0, 0] }]\n".into(),
            "object = \"floor\"\npath = [{ frame = -1, offset = [0, 0, 0] }]\n".into(),
            "object = \"floor\"\npath = [{ frame = 0, offset = [0, 0] }]\n".into(),
            "object = \"floor\"\npath = [{ frame = 0, offset = [nan, 0, 0] }]\n".into(),
            format!("object = \"floor\"\n{still}speed = 2\n"),
        ];
        for dynamic in errors {
            let err = dynamic_scene(&dynamic)
                .err()
                .unwrap_or_else(|| panic!("accepted {dynamic}"));
            assert!(!err.0.contains('\n'), "{err}");
        }
    }

    #[test]
    fn an_area_light_becomes_two_emissive_triangles_facing_along_the_edge_cross_product() {
        let scene = area_scene(
            "center = [0, 2, 0]\nedges = [[2, 0, 0], [0, 0, 1]]\nflux = 3\ncolor = [1, 0.5, 0]\n",
        )
        .unwrap();
        assert!(scene.lights.is_empty());
        assert_eq!(scene.mesh.triangle_count(), 3);
        let emitter = &scene.materials[1];
        assert!(!emitter.two_sided);
        // Scaled by 0.5: a 1 x 0.5 rectangle at height 1, facing -y (x × z = -y).
        let area: f32 = (1..3)
            .map(|t| {
                let [a, b, c] = scene.mesh.triangle(t);
                assert_eq!(scene.mesh.materials[t], 1);
                assert!((scene.mesh.face_normal(t) - Vec3::NEG_Y).length() < 1e-6);
                assert!([a, b, c].iter().all(|p| (p.y - 1.0).abs() < 1e-6));
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        assert!((area - 0.5).abs() < 1e-6, "{area}");
        // Φ = π L A: L = 3 / (π 0.5).
        let radiance = 3.0 / (std::f32::consts::PI * 0.5);
        assert!((emitter.emission - Vec3::new(1.0, 0.5, 0.0) * radiance).length() < 1e-5);
        let two = area_scene(
            "center = [0, 2, 0]\nedges = [[2, 0, 0], [0, 0, 1]]\nflux = 3\ntwo_sided = true\n",
        )
        .unwrap();
        assert!((two.materials[1].emission.x - radiance / 2.0).abs() < 1e-5);
        let given =
            area_scene("center = [0, 2, 0]\nedges = [[2, 0, 0], [0, 0, 1]]\nradiance = 7\n")
                .unwrap();
        assert_eq!(given.materials[1].emission, Vec3::splat(7.0));
    }

    #[test]
    fn area_lights_need_area_and_exactly_one_of_radiance_or_flux() {
        let errors = [
            "center = [0, 2, 0]\nedges = [[2, 0, 0], [4, 0, 0]]\nflux = 1\n",
            "center = [0, 2, 0]\nedges = [[0, 0, 0], [0, 0, 1]]\nflux = 1\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0], [0, 0, 1]]\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0], [0, 0, 1]]\nflux = 1\nradiance = 1\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0], [0, 0, 1]]\nflux = -1\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0]]\nflux = 1\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0], [0, 1]]\nflux = 1\n",
            "center = [0, 2, 0]\nedges = [[1e30, 0, 0], [0, 0, 1e30]]\nflux = 1\n",
            "center = [0, 2, 0]\nedges = [[1, 0, 0], [0, 0, 1]]\nradiance = 1e30\n",
        ];
        for light in errors {
            let err = area_scene(light)
                .err()
                .unwrap_or_else(|| panic!("accepted {light}"));
            assert!(!err.0.contains('\n'), "{err}");
        }
    }
}
