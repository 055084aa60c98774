//! What the viewer lets the user move: each punctual light, and each emitter — the emissive
//! triangles of one material (an area light from a scene file, glTF or MTL `Ke`), moved as one
//! rigid piece. An emitter's vertices are first made its own (copied where other triangles
//! share them, into one contiguous range), so moving it drags no other surface and its new
//! positions are one small buffer write.

use std::ops::Range;

use glam::Vec3;

use super::{LightKind, MAX_POWER, Scene};

/// The tints the viewer cycles a light through: white, warm, cool, red, green, blue.
pub const TINTS: [Vec3; 6] = [
    Vec3::ONE,
    Vec3::new(1.0, 0.8, 0.6),
    Vec3::new(0.6, 0.8, 1.0),
    Vec3::new(1.0, 0.2, 0.2),
    Vec3::new(0.2, 1.0, 0.2),
    Vec3::new(0.2, 0.2, 1.0),
];

/// The dimmest flux (W) a light is dimmed to: it never reaches zero (ILPV's energy ratio needs
/// light before and after).
const MIN_FLUX: f32 = 1e-6;

/// One thing the viewer can move.
#[derive(Clone, Debug, PartialEq)]
pub enum Movable {
    /// `scene.lights[index]`.
    Light(usize),
    /// The triangles of material `material`, whose vertices are `vertices` and no other
    /// triangle's.
    Emitter { material: u32, vertices: Range<u32> },
    /// `scene.dynamic[index]`, moved on top of its path.
    Object(usize),
}

impl Movable {
    /// A short label for the viewer's overlay.
    pub fn describe(&self, scene: &Scene) -> String {
        match self {
            Movable::Light(i) => {
                let light = &scene.lights[*i];
                let kind = match light.kind {
                    LightKind::Spot { .. } => "spot",
                    LightKind::Point => "point",
                    LightKind::Cosine { .. } => "area sample",
                };
                let c = light.color;
                format!(
                    "light {} ({kind}, {:.3e} W, tint {:.1} {:.1} {:.1})",
                    i + 1,
                    light.flux,
                    c.x,
                    c.y,
                    c.z
                )
            }
            Movable::Emitter { material, vertices } => format!(
                "emitter {} ({} vertices)",
                scene.materials[*material as usize].name,
                vertices.len()
            ),
            Movable::Object(i) => format!("dynamic object {}", scene.dynamic[*i].name),
        }
    }
}

impl Scene {
    /// Give every emissive material's triangles vertices of their own, in one contiguous range
    /// per material at the end of the vertex array, and list what can be moved: the punctual
    /// lights, then the emitters, then the dynamic objects. The scene renders exactly as before
    /// (the copies are equal).
    pub fn movables(&mut self) -> Vec<Movable> {
        let mut movables: Vec<Movable> = (0..self.lights.len()).map(Movable::Light).collect();
        for material in 0..self.materials.len() as u32 {
            if self.materials[material as usize].emission.max_element() <= 0.0 {
                continue;
            }
            let mesh = &self.mesh;
            let of_material: Vec<bool> = (0..mesh.triangle_count())
                .map(|t| mesh.materials[t] == material)
                .collect();
            let vertices = self.own_vertices(|t| of_material[t]);
            if !vertices.is_empty() {
                movables.push(Movable::Emitter { material, vertices });
            }
        }
        movables.extend((0..self.dynamic.len()).map(Movable::Object));
        movables
    }

    /// Move `which` by `step` (metres). Bounds grow to take in a moved emitter; a dynamic object
    /// stays inside them (see [`Scene::nudge`]) and moves at the next [`Scene::pose`].
    pub fn move_by(&mut self, which: &Movable, step: Vec3) {
        match which {
            Movable::Light(i) => self.lights[*i].position += step,
            Movable::Emitter { vertices, .. } => {
                for i in vertices.clone() {
                    let p = &mut self.mesh.positions[i as usize];
                    *p += step;
                    self.bounds_min = self.bounds_min.min(*p);
                    self.bounds_max = self.bounds_max.max(*p);
                }
            }
            Movable::Object(i) => self.nudge(*i, step),
        }
    }

    /// Scale a punctual light's flux by `factor`, within [1e-6 W, vkgi's power limit]; false
    /// for an emitter (its radiance is a material's).
    pub fn dim(&mut self, which: &Movable, factor: f32) -> bool {
        let Movable::Light(i) = which else {
            return false;
        };
        let light = &mut self.lights[*i];
        let most = MAX_POWER / light.color.max_element().max(1e-6);
        light.flux = (light.flux * factor).clamp(MIN_FLUX, most);
        true
    }

    /// Give a punctual light the tint after its own in [`TINTS`] (white after any other
    /// colour); false for an emitter.
    pub fn retint(&mut self, which: &Movable) -> bool {
        let Movable::Light(i) = which else {
            return false;
        };
        let light = &mut self.lights[*i];
        let next = TINTS
            .iter()
            .position(|&t| t == light.color)
            .map_or(0, |k| (k + 1) % TINTS.len());
        light.color = TINTS[next];
        true
    }

    /// Turn a spot light's axis by `yaw` about the vertical and `pitch` about its horizontal
    /// side (radians), never past straight up or down; false for anything but a spot light.
    pub fn aim(&mut self, which: &Movable, yaw: f32, pitch: f32) -> bool {
        let Movable::Light(i) = which else {
            return false;
        };
        let LightKind::Spot { direction, .. } = &mut self.lights[*i].kind else {
            return false;
        };
        let turned = glam::Quat::from_rotation_y(yaw) * *direction;
        let side = turned.cross(Vec3::Y).normalize_or(Vec3::X);
        let pitched = glam::Quat::from_axis_angle(side, pitch) * turned;
        // Keep off the vertical, where the side axis is undefined.
        if pitched.y.abs() < 0.999 || pitched.y.abs() < turned.y.abs() {
            *direction = pitched.normalize();
        } else {
            *direction = turned.normalize();
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn punctual_lights_dim_retint_and_aim_and_emitters_do_not() {
        let mut scene = Scene::load("cornell").unwrap();
        let light = Movable::Light(0);
        let flux = scene.lights[0].flux;
        assert!(scene.dim(&light, 0.5));
        assert_eq!(scene.lights[0].flux, 0.5 * flux);
        for _ in 0..200 {
            scene.dim(&light, 1e-3);
        }
        assert_eq!(scene.lights[0].flux, MIN_FLUX);
        assert!(scene.retint(&light));
        assert_eq!(scene.lights[0].color, TINTS[1]);
        for _ in 1..TINTS.len() {
            scene.retint(&light);
        }
        assert_eq!(scene.lights[0].color, Vec3::ONE, "the tints cycle");
        // The Cornell spot points straight down: yaw alone keeps it there; pitch tilts it, and
        // never past the vertical.
        assert!(scene.aim(&light, 0.3, 0.0));
        let LightKind::Spot { direction, .. } = scene.lights[0].kind else {
            unreachable!()
        };
        assert!((direction - Vec3::NEG_Y).length() < 1e-5);
        for _ in 0..100 {
            scene.aim(&light, 0.01, 0.05);
        }
        let LightKind::Spot { direction, .. } = scene.lights[0].kind else {
            unreachable!()
        };
        assert!((direction.length() - 1.0).abs() < 1e-5 && direction.y.abs() < 0.9995);
        let mut area = Scene::load("cornell-area").unwrap();
        let emitter = area
            .movables()
            .into_iter()
            .find(|m| matches!(m, Movable::Emitter { .. }));
        let emitter = emitter.unwrap();
        assert!(
            !area.dim(&emitter, 0.5) && !area.retint(&emitter) && !area.aim(&emitter, 0.1, 0.1)
        );
    }

    #[test]
    fn an_emitter_moves_alone_and_its_light_samples_follow() {
        let mut scene = Scene::load("cornell-area").unwrap();
        let before = scene.clone();
        let movables = scene.movables();
        let emitter = movables
            .iter()
            .find(|m| matches!(m, Movable::Emitter { .. }))
            .expect("the ceiling light is an emitter")
            .clone();
        // Detaching changes nothing that renders.
        for t in 0..scene.mesh.triangle_count() {
            assert_eq!(scene.mesh.triangle(t), before.mesh.triangle(t));
        }
        let step = Vec3::new(0.05, -0.1, 0.02);
        scene.move_by(&emitter, step);
        let Movable::Emitter { material, .. } = emitter else {
            unreachable!()
        };
        for t in 0..scene.mesh.triangle_count() {
            let expected = if scene.mesh.materials[t] == material {
                before.mesh.triangle(t).map(|p| p + step)
            } else {
                before.mesh.triangle(t)
            };
            assert_eq!(scene.mesh.triangle(t), expected, "triangle {t}");
        }
        let centre = |s: &Scene| {
            let lights = s.raster_lights();
            lights.iter().map(|l| l.position).sum::<Vec3>() / lights.len() as f32
        };
        assert!((centre(&scene) - centre(&before) - step).length() < 1e-5);
    }
}
