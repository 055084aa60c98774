//! Dynamic objects: sets of triangles that move as rigid pieces while the scene renders, by a
//! scripted path of keyframes (a scene file's `[[dynamic]]`) and by the viewer's keys. Each
//! object's vertices are made its own (as an emitter's, see [`super::movable`]), so posing it
//! writes one contiguous range of the vertex buffer and drags no other surface. The scene's
//! bounds take in every place the path visits, so lattices fitted to the scene hold the object
//! wherever it goes.

use std::ops::Range;

use glam::Vec3;

use super::{MAX_COORDINATE, Scene};
use crate::error::InputError;

/// Most keyframes one path may have.
pub const MAX_KEYFRAMES: usize = 100_000;
/// Latest frame a keyframe may name.
pub const MAX_KEYFRAME: u64 = 1_000_000_000;

/// An axis-aligned box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The box around `points` (None when there are none).
    pub fn around(points: impl IntoIterator<Item = Vec3>) -> Option<Aabb> {
        points.into_iter().fold(None, |b: Option<Aabb>, p| {
            Some(match b {
                None => Aabb { min: p, max: p },
                Some(b) => Aabb {
                    min: b.min.min(p),
                    max: b.max.max(p),
                },
            })
        })
    }

    pub fn translated(self, by: Vec3) -> Aabb {
        Aabb {
            min: self.min + by,
            max: self.max + by,
        }
    }

    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
}

/// A scripted path: offsets (scene units) at keyframes, linear between them, the first one's
/// before it and the last one's after it, or repeated from the first when `looped`.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// `(frame, offset)`, frames strictly increasing; never empty.
    keys: Vec<(u64, Vec3)>,
    looped: bool,
}

impl Path {
    /// A path through `keys`; one line naming what is wrong when the keys are not strictly
    /// increasing frames (at most [`MAX_KEYFRAME`]) with finite offsets within vkgi's
    /// coordinate limit, or there are none or over [`MAX_KEYFRAMES`].
    pub fn new(keys: Vec<(u64, Vec3)>, looped: bool) -> Result<Path, String> {
        if keys.is_empty() || keys.len() > MAX_KEYFRAMES {
            return Err(format!(
                "a path needs 1 to {MAX_KEYFRAMES} keyframes (it has {})",
                keys.len()
            ));
        }
        for (i, &(frame, offset)) in keys.iter().enumerate() {
            if frame > MAX_KEYFRAME {
                return Err(format!(
                    "keyframe {}: frame {frame} is past vkgi's limit of {MAX_KEYFRAME}",
                    i + 1
                ));
            }
            if !(offset.is_finite() && offset.abs().max_element() <= MAX_COORDINATE) {
                return Err(format!(
                    "keyframe {}: the offset must be finite and within ±{MAX_COORDINATE:e}",
                    i + 1
                ));
            }
            if i > 0 && frame <= keys[i - 1].0 {
                return Err(format!(
                    "keyframe {}: frame {frame} does not follow frame {} (frames must increase)",
                    i + 1,
                    keys[i - 1].0
                ));
            }
        }
        Ok(Path { keys, looped })
    }

    /// A path that stays at `offset`.
    pub fn still(offset: Vec3) -> Path {
        Path {
            keys: vec![(0, offset)],
            looped: false,
        }
    }

    pub fn keys(&self) -> &[(u64, Vec3)] {
        &self.keys
    }

    pub fn looped(&self) -> bool {
        self.looped
    }

    /// The offset at `frame`.
    pub fn at(&self, frame: u64) -> Vec3 {
        let (first, last) = (self.keys[0], self.keys[self.keys.len() - 1]);
        let span = last.0 - first.0;
        let frame = if self.looped && span > 0 && frame > last.0 {
            first.0 + (frame - first.0) % span
        } else {
            frame
        };
        if frame <= first.0 {
            return first.1;
        }
        let next = self.keys.partition_point(|&(f, _)| f <= frame);
        let Some(&(f1, b)) = self.keys.get(next) else {
            return last.1;
        };
        let (f0, a) = self.keys[next - 1];
        let t = (frame - f0) as f64 / (f1 - f0) as f64;
        (a.as_dvec3() + (b - a).as_dvec3() * t).as_vec3()
    }

    /// Every offset the path takes lies in the box of its keyframes' offsets.
    fn offset_bounds(&self) -> Aabb {
        Aabb::around(self.keys.iter().map(|k| k.1)).expect("a path has keyframes")
    }
}

/// One dynamic object.
#[derive(Clone, Debug, PartialEq)]
pub struct DynamicObject {
    pub name: String,
    /// Its vertices, which no other triangle uses.
    pub vertices: Range<u32>,
    /// Their positions at offset zero (where the mesh file puts them).
    pub rest: Vec<Vec3>,
    pub path: Path,
    /// Where the viewer's keys moved it, on top of its path.
    pub nudge: Vec3,
    /// The offset it is posed at now.
    pub offset: Vec3,
    /// The box of `rest`.
    rest_bounds: Aabb,
}

impl DynamicObject {
    /// Its box at `offset`.
    pub fn bounds_at(&self, offset: Vec3) -> Aabb {
        self.rest_bounds.translated(offset)
    }
}

/// An object [`Scene::pose`] moved: its vertices and its boxes before and after.
#[derive(Clone, Debug, PartialEq)]
pub struct Moved {
    pub object: usize,
    pub vertices: Range<u32>,
    pub before: Aabb,
    pub after: Aabb,
}

impl Moved {
    /// The world boxes whose geometry changed: where the object was and where it is.
    pub fn regions(moved: &[Moved]) -> Vec<Aabb> {
        moved.iter().flat_map(|m| [m.before, m.after]).collect()
    }
}

impl Scene {
    /// Give the triangles `select` picks vertices of their own, in one contiguous range at the
    /// end of the vertex array (copies where other triangles share them), and return it. The
    /// scene renders exactly as before (the copies are equal).
    pub(super) fn own_vertices(&mut self, select: impl Fn(usize) -> bool) -> Range<u32> {
        let first = self.mesh.positions.len() as u32;
        let mut copied = std::collections::HashMap::new();
        for t in 0..self.mesh.triangle_count() {
            if !select(t) {
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
        first..self.mesh.positions.len() as u32
    }

    /// Make `triangles` one dynamic object called `name` that follows `path`, posed at frame 0,
    /// and widen the scene's bounds to every place the path takes it. One line naming what is
    /// wrong when there are no triangles, one is emissive or already dynamic, the name is taken,
    /// or the path leaves vkgi's coordinate limit.
    pub fn add_dynamic(
        &mut self,
        name: &str,
        triangles: &[usize],
        path: Path,
    ) -> Result<(), InputError> {
        let scene = self.name.clone();
        let err = |m: String| Err(InputError::new(format!("scene '{scene}': {m}")));
        if triangles.is_empty() {
            return err(format!("dynamic object '{name}' has no triangles"));
        }
        if self.dynamic.iter().any(|o| o.name == name) {
            return err(format!("dynamic object '{name}' is declared twice"));
        }
        let mut chosen = vec![false; self.mesh.triangle_count()];
        for &t in triangles {
            let emissive = self.materials[self.mesh.materials[t] as usize]
                .emission
                .max_element()
                > 0.0;
            if emissive {
                return err(format!(
                    "dynamic object '{name}' has emissive triangles (emitters move with the viewer's arrow keys, not by a path)"
                ));
            }
            let vertices = self.mesh.indices[t];
            if let Some(o) = self
                .dynamic
                .iter()
                .find(|o| vertices.iter().all(|v| o.vertices.contains(v)))
            {
                return err(format!(
                    "dynamic object '{name}' shares triangles with dynamic object '{}'",
                    o.name
                ));
            }
            chosen[t] = true;
        }
        let vertices = self.own_vertices(|t| chosen[t]);
        let rest: Vec<Vec3> =
            self.mesh.positions[vertices.start as usize..vertices.end as usize].to_vec();
        let rest_bounds = Aabb::around(rest.iter().copied()).expect("the object has vertices");
        let offsets = path.offset_bounds();
        let swept = Aabb {
            min: rest_bounds.min + offsets.min,
            max: rest_bounds.max + offsets.max,
        };
        let reach = swept.min.abs().max(swept.max.abs()).max_element();
        if !(reach.is_finite() && reach <= MAX_COORDINATE) {
            return err(format!(
                "dynamic object '{name}': its path reaches coordinate {reach:e}, beyond vkgi's limit of ±{MAX_COORDINATE:e}"
            ));
        }
        self.bounds_min = self.bounds_min.min(swept.min);
        self.bounds_max = self.bounds_max.max(swept.max);
        self.dynamic.push(DynamicObject {
            name: name.to_string(),
            vertices,
            rest,
            path,
            nudge: Vec3::ZERO,
            offset: Vec3::ZERO,
            rest_bounds,
        });
        self.pose(0);
        Ok(())
    }

    /// Pose every dynamic object for `frame` (its path there, plus the viewer's nudge) and
    /// return those that moved.
    pub fn pose(&mut self, frame: u64) -> Vec<Moved> {
        let mut moved = Vec::new();
        for (index, object) in self.dynamic.iter_mut().enumerate() {
            let offset = object.path.at(frame) + object.nudge;
            if offset == object.offset {
                continue;
            }
            let range = object.vertices.start as usize..object.vertices.end as usize;
            for (p, rest) in self.mesh.positions[range].iter_mut().zip(&object.rest) {
                *p = *rest + offset;
            }
            moved.push(Moved {
                object: index,
                vertices: object.vertices.clone(),
                before: object.bounds_at(object.offset),
                after: object.bounds_at(offset),
            });
            object.offset = offset;
        }
        moved
    }

    /// Move dynamic object `index` by `step` on top of its path (the viewer's keys), as far as
    /// the scene's bounds allow where its path last posed it; the next [`Scene::pose`] applies
    /// it.
    pub fn nudge(&mut self, index: usize, step: Vec3) {
        let (min, max) = (self.bounds_min, self.bounds_max);
        let object = &mut self.dynamic[index];
        let at = object.offset - object.nudge;
        let lowest = min - object.rest_bounds.min - at;
        let highest = max - object.rest_bounds.max - at;
        object.nudge = (object.nudge + step).clamp(lowest.min(highest), highest.max(lowest));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(keys: &[(u64, [f32; 3])], looped: bool) -> Path {
        Path::new(
            keys.iter().map(|&(f, o)| (f, Vec3::from(o))).collect(),
            looped,
        )
        .unwrap()
    }

    #[test]
    fn a_path_holds_before_and_after_and_is_linear_between_keyframes() {
        let p = path(
            &[
                (10, [0.0, 0.0, 0.0]),
                (20, [1.0, 2.0, 0.0]),
                (40, [1.0, 0.0, 0.0]),
            ],
            false,
        );
        assert_eq!(p.at(0), Vec3::ZERO);
        assert_eq!(p.at(10), Vec3::ZERO);
        assert_eq!(p.at(15), Vec3::new(0.5, 1.0, 0.0));
        assert_eq!(p.at(20), Vec3::new(1.0, 2.0, 0.0));
        assert_eq!(p.at(30), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(p.at(1000), Vec3::new(1.0, 0.0, 0.0));
        let looped = path(&[(10, [0.0, 0.0, 0.0]), (20, [1.0, 0.0, 0.0])], true);
        assert_eq!(looped.at(25), Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(looped.at(30), Vec3::ZERO);
        assert_eq!(looped.at(5), Vec3::ZERO);
        assert_eq!(Path::still(Vec3::X).at(7), Vec3::X);
    }

    #[test]
    fn bad_paths_are_refused_with_one_line() {
        let bad = [
            vec![],
            vec![(3, Vec3::ZERO), (3, Vec3::X)],
            vec![(3, Vec3::ZERO), (2, Vec3::X)],
            vec![(0, Vec3::splat(f32::NAN))],
            vec![(0, Vec3::splat(2e9))],
            vec![(MAX_KEYFRAME + 1, Vec3::ZERO)],
        ];
        for keys in bad {
            let e = Path::new(keys.clone(), false).expect_err(&format!("{keys:?}"));
            assert!(!e.contains('\n'), "{e}");
        }
    }

    fn tall_block(scene: &Scene) -> Vec<usize> {
        // The Cornell box's last 10 triangles are the tall block.
        let n = scene.mesh.triangle_count();
        (n - 10..n).collect()
    }

    #[test]
    fn a_dynamic_object_moves_alone_and_the_bounds_take_in_its_path() {
        let mut scene = Scene::load("cornell").unwrap();
        let before = scene.clone();
        let block = tall_block(&scene);
        let p = path(&[(0, [0.0, 0.0, 0.0]), (10, [-0.1, 0.0, -0.3])], false);
        scene.add_dynamic("tall", &block, p).unwrap();
        for t in 0..scene.mesh.triangle_count() {
            assert_eq!(scene.mesh.triangle(t), before.mesh.triangle(t), "frame 0");
        }
        assert!(
            scene.bounds_min.z < before.bounds_min.z,
            "the path leaves the box"
        );
        assert!(scene.pose(0).is_empty());
        let moved = scene.pose(5);
        assert_eq!(moved.len(), 1);
        let step = Vec3::new(-0.05, 0.0, -0.15);
        assert!((moved[0].after.min - moved[0].before.min - step).length() < 1e-6);
        for t in 0..scene.mesh.triangle_count() {
            let expected = if block.contains(&t) {
                before.mesh.triangle(t).map(|p| p + step)
            } else {
                before.mesh.triangle(t)
            };
            for (a, b) in scene.mesh.triangle(t).iter().zip(expected) {
                assert!((*a - b).length() < 1e-6, "triangle {t}");
            }
        }
        assert!(scene.pose(5).is_empty(), "posed already");
        // The keys push it further, never out of the bounds.
        scene.nudge(0, Vec3::new(0.0, 10.0, 0.0));
        let moved = scene.pose(5);
        assert!((moved[0].after.max.y - scene.bounds_max.y).abs() < 1e-6);
    }

    #[test]
    fn dynamic_objects_must_be_new_non_emissive_triangles() {
        let mut scene = Scene::load("cornell").unwrap();
        let block = tall_block(&scene);
        assert!(
            scene
                .add_dynamic("none", &[], Path::still(Vec3::ZERO))
                .is_err()
        );
        scene
            .add_dynamic("tall", &block, Path::still(Vec3::ZERO))
            .unwrap();
        let twice = scene.add_dynamic("again", &block[..2], Path::still(Vec3::ZERO));
        assert!(twice.unwrap_err().0.contains("shares triangles"));
        let named = scene.add_dynamic("tall", &[0], Path::still(Vec3::ZERO));
        assert!(named.unwrap_err().0.contains("twice"));
        let mut area = Scene::load("cornell-area").unwrap();
        let emissive: Vec<usize> = (0..area.mesh.triangle_count())
            .filter(|&t| area.materials[area.mesh.materials[t] as usize].emission.x > 0.0)
            .collect();
        assert!(
            area.add_dynamic("lamp", &emissive, Path::still(Vec3::ZERO))
                .is_err()
        );
    }
}
