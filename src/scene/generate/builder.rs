//! A small mesh builder for the generated scenes: materials, quads (optionally subdivided into
//! patches, as seed 004's subdivided boxes), boxes and transforms.

use glam::{Mat4, Vec2, Vec3};

use crate::error::InputError;
use crate::scene::{Camera, Light, Material, Mesh, Scene};

#[derive(Default)]
pub struct Builder {
    mesh: Mesh,
    materials: Vec<Material>,
    /// Applied to every vertex added from now on.
    transform: Option<Mat4>,
}

impl Builder {
    /// A diffuse material (one-sided emission, if any); returns its index.
    pub fn material(&mut self, name: &str, albedo: Vec3, emission: Vec3) -> u32 {
        self.materials.push(Material {
            emission,
            ..Material::diffuse(name, albedo)
        });
        self.materials.len() as u32 - 1
    }

    /// Transform every vertex added until the next call (None: the identity).
    pub fn set_transform(&mut self, transform: Option<Mat4>) {
        self.transform = transform;
    }

    fn place(&self, p: Vec3) -> Vec3 {
        self.transform.map_or(p, |t| t.transform_point3(p))
    }

    /// A planar quad `a b c d` (winding gives its front face), split into `2^split` x `2^split`
    /// patches of two triangles each, with shared vertices.
    pub fn quad(&mut self, [a, b, c, d]: [Vec3; 4], material: u32, split: u32) {
        let n = 1usize << split.min(8);
        let first = self.mesh.positions.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let p =
                    a * (1.0 - u) * (1.0 - v) + b * u * (1.0 - v) + c * u * v + d * (1.0 - u) * v;
                let p = self.place(p);
                self.mesh.positions.push(p);
                self.mesh.normals.push(Vec3::ZERO);
                self.mesh.texcoords.push(Vec2::new(u, v));
            }
        }
        let at = |i: usize, j: usize| first + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                let (p, q, r, s) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                self.mesh.indices.push([p, q, r]);
                self.mesh.indices.push([p, r, s]);
                self.mesh.materials.push(material);
                self.mesh.materials.push(material);
            }
        }
    }

    /// An axis-aligned box from `min` to `max`, its faces outward (a solid) or inward (a room).
    pub fn cuboid(&mut self, min: Vec3, max: Vec3, material: u32, inward: bool, split: u32) {
        let c = |x: bool, y: bool, z: bool| {
            Vec3::new(
                if x { max.x } else { min.x },
                if y { max.y } else { min.y },
                if z { max.z } else { min.z },
            )
        };
        // Outward winding, counter-clockwise seen from outside.
        let faces = [
            [
                c(false, false, false),
                c(false, false, true),
                c(false, true, true),
                c(false, true, false),
            ],
            [
                c(true, false, false),
                c(true, true, false),
                c(true, true, true),
                c(true, false, true),
            ],
            [
                c(false, false, false),
                c(true, false, false),
                c(true, false, true),
                c(false, false, true),
            ],
            [
                c(false, true, false),
                c(false, true, true),
                c(true, true, true),
                c(true, true, false),
            ],
            [
                c(false, false, false),
                c(false, true, false),
                c(true, true, false),
                c(true, false, false),
            ],
            [
                c(false, false, true),
                c(true, false, true),
                c(true, true, true),
                c(false, true, true),
            ],
        ];
        for [a, b, cc, d] in faces {
            let quad = if inward { [a, d, cc, b] } else { [a, b, cc, d] };
            self.quad(quad, material, split);
        }
    }

    /// A triangle with its own vertices.
    pub fn triangle(&mut self, corners: [Vec3; 3], material: u32) {
        let corners = corners.map(|p| self.place(p));
        self.mesh.push_triangle(corners, [Vec3::ZERO; 3], material);
    }

    /// The scene, scaled by `scale` (mesh, lights and camera), validated.
    pub fn finish(
        mut self,
        name: &str,
        scale: f32,
        mut lights: Vec<Light>,
        mut camera: Camera,
    ) -> Result<Scene, InputError> {
        for p in &mut self.mesh.positions {
            *p *= scale;
        }
        for l in &mut lights {
            l.position *= scale;
        }
        camera.position *= scale;
        camera.target *= scale;
        Scene::new(name.to_string(), self.mesh, self.materials, lights, camera)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_subdivide_into_shared_vertex_patches_with_the_quad_winding() {
        let mut b = Builder::default();
        let m = b.material("m", Vec3::splat(0.5), Vec3::ZERO);
        let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        b.quad(quad, m, 2);
        assert_eq!(b.mesh.triangle_count(), 2 * 16);
        assert_eq!(b.mesh.positions.len(), 25);
        for t in 0..b.mesh.triangle_count() {
            assert!((b.mesh.face_normal(t) - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn rooms_face_inward_and_solids_outward() {
        let mut b = Builder::default();
        let m = b.material("m", Vec3::splat(0.5), Vec3::ZERO);
        b.cuboid(Vec3::splat(-1.0), Vec3::splat(1.0), m, true, 0);
        for t in 0..b.mesh.triangle_count() {
            let [p, q, r] = b.mesh.triangle(t);
            let centre = (p + q + r) / 3.0;
            assert!(
                b.mesh.face_normal(t).dot(centre) < 0.0,
                "room face {t} points out"
            );
        }
        let mut s = Builder::default();
        let m = s.material("m", Vec3::splat(0.5), Vec3::ZERO);
        s.cuboid(Vec3::splat(-1.0), Vec3::splat(1.0), m, false, 1);
        assert_eq!(s.mesh.triangle_count(), 6 * 8);
        for t in 0..s.mesh.triangle_count() {
            let [p, q, r] = s.mesh.triangle(t);
            let centre = (p + q + r) / 3.0;
            assert!(
                s.mesh.face_normal(t).dot(centre) > 0.0,
                "solid face {t} points in"
            );
        }
    }
}
