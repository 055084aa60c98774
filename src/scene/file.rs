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
//! ```

use std::path::Path;

use glam::Vec3;
use serde::{Deserialize, Deserializer};

use super::obj::{self, ObjSource};
use super::{Camera, Light, LightKind, Scene};
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
}

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
    pub fn into_scene(
        self,
        name: String,
        mesh: super::Mesh,
        materials: Vec<super::Material>,
    ) -> Result<Scene, InputError> {
        let s = self.scale;
        let v = |a: [f32; 3]| Vec3::from(a) * s;
        let lights = self
            .lights
            .iter()
            .map(|l| match *l {
                LightFile::Spot {
                    position,
                    direction,
                    cone_angle,
                    penumbra,
                    flux,
                    color,
                } => Light {
                    position: v(position),
                    kind: LightKind::Spot {
                        direction: Vec3::from(direction),
                        cone_angle_deg: cone_angle,
                        penumbra_deg: penumbra,
                    },
                    flux,
                    color: Vec3::from(color.unwrap_or([1.0; 3])),
                },
                LightFile::Point {
                    position,
                    flux,
                    color,
                } => Light {
                    position: v(position),
                    kind: LightKind::Point,
                    flux,
                    color: Vec3::from(color.unwrap_or([1.0; 3])),
                },
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
        Scene::new(name, mesh, materials, lights, camera)
    }
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
    let (mesh, materials) = obj::load(&source, file.scale)?;
    file.into_scene(name.to_string(), mesh, materials)
}

/// Load a scene file from disk; its mesh path is relative to the file.
pub fn load_scene_file(path: &Path) -> Result<Scene, InputError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new(format!("{origin}: cannot read scene file: {e}")))?;
    let file = SceneFile::parse(&text, &origin)?;
    let mesh_path = path.parent().unwrap_or(Path::new(".")).join(&file.mesh);
    let (mesh, materials) = obj::load(&ObjSource::File(&mesh_path), file.scale)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    file.into_scene(name, mesh, materials)
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
}
