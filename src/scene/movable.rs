//! What the viewer lets the user move: each punctual light, and each emitter — the emissive
//! triangles of one material (an area light from a scene file, glTF or MTL `Ke`), moved as one
//! rigid piece. An emitter's vertices are first made its own (copied where other triangles
//! share them, into one contiguous range), so moving it drags no other surface and its new
//! positions are one small buffer write.

use std::ops::Range;

use glam::Vec3;

use super::{LightKind, Scene};

/// One thing the viewer can move.
#[derive(Clone, Debug, PartialEq)]
pub enum Movable {
    /// `scene.lights[index]`.
    Light(usize),
    /// The triangles of material `material`, whose vertices are `vertices` and no other
    /// triangle's.
    Emitter { material: u32, vertices: Range<u32> },
}

impl Movable {
    /// A short label for the viewer's overlay.
    pub fn describe(&self, scene: &Scene) -> String {
        match self {
            Movable::Light(i) => {
                let kind = match scene.lights[*i].kind {
                    LightKind::Spot { .. } => "spot",
                    LightKind::Point => "point",
                    LightKind::Cosine { .. } => "area sample",
                };
                format!("light {} ({kind})", i + 1)
            }
            Movable::Emitter { material, vertices } => format!(
                "emitter {} ({} vertices)",
                scene.materials[*material as usize].name,
                vertices.len()
            ),
        }
    }
}

impl Scene {
    /// Give every emissive material's triangles vertices of their own, in one contiguous range
    /// per material at the end of the vertex array, and list what can be moved: the punctual
    /// lights, then the emitters. The scene renders exactly as before (the copies are equal).
    pub fn movables(&mut self) -> Vec<Movable> {
        let mut movables: Vec<Movable> = (0..self.lights.len()).map(Movable::Light).collect();
        for material in 0..self.materials.len() as u32 {
            if self.materials[material as usize].emission.max_element() <= 0.0 {
                continue;
            }
            let first = self.mesh.positions.len() as u32;
            let mut copied = std::collections::HashMap::new();
            for t in 0..self.mesh.triangle_count() {
                if self.mesh.materials[t] != material {
                    continue;
                }
                for corner in 0..3 {
                    let old = self.mesh.indices[t][corner];
                    let new = *copied.entry(old).or_insert_with(|| {
                        let mesh = &mut self.mesh;
                        mesh.positions.push(mesh.positions[old as usize]);
                        mesh.normals.push(mesh.normals[old as usize]);
                        mesh.texcoords.push(mesh.texcoords[old as usize]);
                        mesh.positions.len() as u32 - 1
                    });
                    self.mesh.indices[t][corner] = new;
                }
            }
            let end = self.mesh.positions.len() as u32;
            if end > first {
                movables.push(Movable::Emitter {
                    material,
                    vertices: first..end,
                });
            }
        }
        movables
    }

    /// Move `which` by `step` (metres). Bounds grow to take in a moved emitter.
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
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
