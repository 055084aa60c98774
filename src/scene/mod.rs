//! Scenes: triangle meshes with Lambertian materials (OBJ + MTL through tobj), punctual lights
//! and a camera, from a built-in name, a scene file (TOML) or a bare OBJ.

pub mod builtin;
pub mod bvh;
pub mod camera;
pub mod file;
pub mod gpu;
pub mod intersect;
pub mod light;
pub mod obj;

use std::path::Path;

use glam::Vec3;

pub use camera::Camera;
pub use light::{Light, LightKind};

use crate::error::InputError;

/// A Lambertian material: diffuse albedo in [0, 1] and emitted radiance (W/(m²·sr)).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub albedo: Vec3,
    pub emission: Vec3,
}

/// Triangles as a flat list: corners `3t, 3t+1, 3t+2` belong to triangle `t`.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Shading normal per corner (the face normal where the OBJ has none).
    pub normals: Vec<Vec3>,
    /// Material index per triangle.
    pub materials: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.materials.len()
    }

    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        [
            self.positions[3 * t],
            self.positions[3 * t + 1],
            self.positions[3 * t + 2],
        ]
    }

    /// Unit geometric normal of triangle `t` (by winding; shading flips it toward the viewer).
    pub fn face_normal(&self, t: usize) -> Vec3 {
        let [a, b, c] = self.triangle(t);
        (b - a).cross(c - a).normalize_or_zero()
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
}

impl Scene {
    /// Load a scene: a built-in name (`cornell`, `two-rooms`), a `.toml` scene file, or a bare
    /// `.obj` (then a point light and camera are framed from its bounds).
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
            Some("obj") => {
                let (mesh, materials) = obj::load(&obj::ObjSource::File(path), 1.0)?;
                let name = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "scene".into());
                Scene::framed(name, mesh, materials)
            }
            _ => Err(InputError::new(format!(
                "unknown scene '{spec}': expected a built-in name ({}), a .toml scene file or an .obj mesh",
                builtin::NAMES.join(", ")
            ))),
        }
    }

    /// A scene around a bare mesh: camera from the front, a point light above and in front.
    pub fn framed(name: String, mesh: Mesh, materials: Vec<Material>) -> Result<Scene, InputError> {
        let (min, max) = mesh.bounds();
        let camera = Camera::framing(min, max);
        let radius = 0.5 * (max - min).length().max(1e-3);
        let center = 0.5 * (min + max);
        let position = center + Vec3::new(0.35, 1.2, 1.6) * radius;
        let distance = (position - center).length();
        // About 3 W/m² at the centre of the bounds: a mid-grey exposure.
        let flux = 3.0 * 4.0 * std::f32::consts::PI * distance * distance;
        let light = Light {
            position,
            kind: LightKind::Point,
            flux,
            color: Vec3::ONE,
        };
        Scene::new(name, mesh, materials, vec![light], camera)
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
        let emissive = materials.iter().any(|m| m.emission.max_element() > 0.0);
        if lights.is_empty() && !emissive {
            return Err(InputError::new(format!(
                "scene '{name}' has no light: add a [[light]] to the scene file or an emissive (Ke) material"
            )));
        }
        for (i, light) in lights.iter().enumerate() {
            validate_light(i, light)
                .map_err(|m| InputError::new(format!("scene '{name}': {m}")))?;
        }
        let camera_ok = [camera.position, camera.target, camera.up]
            .iter()
            .all(|v| v.is_finite())
            && (camera.target - camera.position).length() > 0.0
            && camera.up.cross(camera.target - camera.position).length() > 0.0
            && camera.vfov_deg.is_finite()
            && camera.vfov_deg > 0.1
            && camera.vfov_deg < 179.0;
        if !camera_ok {
            return Err(InputError::new(format!(
                "scene '{name}': the camera needs finite position/target/up, a target away from the \
                 position, an up vector not along the view, and a field of view in (0.1, 179) degrees"
            )));
        }
        let (bounds_min, bounds_max) = mesh.bounds();
        Ok(Scene {
            name,
            mesh,
            materials,
            lights,
            camera,
            bounds_min,
            bounds_max,
        })
    }

    /// Bounds of the mesh and lights together.
    pub fn extended_bounds(&self) -> (Vec3, Vec3) {
        self.lights
            .iter()
            .fold((self.bounds_min, self.bounds_max), |(lo, hi), l| {
                (lo.min(l.position), hi.max(l.position))
            })
    }
}

fn validate_light(index: usize, light: &Light) -> Result<(), String> {
    let what = format!("light {}", index + 1);
    if !light.position.is_finite() {
        return Err(format!("{what}: position must be finite"));
    }
    if !(light.flux.is_finite() && light.flux >= 0.0) {
        return Err(format!(
            "{what}: flux must be a finite number of watts >= 0"
        ));
    }
    if !(light.color.is_finite() && light.color.min_element() >= 0.0) {
        return Err(format!("{what}: color components must be finite and >= 0"));
    }
    if let LightKind::Spot {
        direction,
        cone_angle_deg,
        penumbra_deg,
    } = light.kind
    {
        if !(direction.is_finite() && direction.length() > 0.0) {
            return Err(format!(
                "{what}: direction must be a finite, non-zero vector"
            ));
        }
        if !(cone_angle_deg.is_finite() && cone_angle_deg > 0.0 && cone_angle_deg <= 85.0) {
            return Err(format!(
                "{what}: cone_angle is the half-angle of the cone and must be in (0, 85] degrees"
            ));
        }
        if !(penumbra_deg.is_finite() && (0.0..=cone_angle_deg).contains(&penumbra_deg)) {
            return Err(format!(
                "{what}: penumbra must be in [0, cone_angle] degrees"
            ));
        }
    }
    Ok(())
}
