//! The CAVE of seed 000: a cube of projection walls around a tracked head. Each wall is a
//! window into the scene, rendered with an off-axis (asymmetric) frustum from the head
//! (Kooima's generalised perspective projection), so walls meet seamlessly at their edges.

use glam::{Mat4, Vec3, Vec4};

use crate::render::Eye;
use crate::scene::Scene;
use crate::view::fly::FlyCamera;

/// A wall: its lower-left corner and the vectors along its bottom and left edges, as seen
/// from inside the cube.
#[derive(Clone, Copy, Debug)]
pub struct Wall {
    pub name: &'static str,
    pub corner: Vec3,
    pub right: Vec3,
    pub up: Vec3,
}

impl Wall {
    /// The wall widened by half a pixel of an image `pixels` wide on every side, so that the
    /// image's first and last pixel centres lie on the wall's edges: two walls that meet then
    /// draw their shared edge in both images, through the same points (projectors that overlap
    /// by a pixel).
    pub fn edge_centred(&self, pixels: u32) -> Wall {
        let half = 0.5 / (pixels.max(2) - 1) as f32;
        Wall {
            name: self.name,
            corner: self.corner - (self.right + self.up) * half,
            right: self.right * (1.0 + 2.0 * half),
            up: self.up * (1.0 + 2.0 * half),
        }
    }
}

/// Refuse a CAVE wall size (a fraction of the scene's diagonal) outside (0, 100].
pub fn check_size(size: f32) -> Result<(), crate::error::InputError> {
    if size.is_finite() && size > 0.0 && size <= 100.0 {
        Ok(())
    } else {
        Err(crate::error::InputError::new(format!(
            "--cave-size {size} must be in (0, 100]"
        )))
    }
}

/// A wall's name, as `vkgi cave-node --wall` takes it.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallName {
    Front,
    Left,
    Right,
    Floor,
    Back,
    Ceiling,
}

impl WallName {
    /// The wall's index in [`Cave::all_walls`] (the first four are [`Cave::walls`]).
    pub fn index(self) -> usize {
        self as usize
    }

    pub fn name(self) -> &'static str {
        ["front", "left", "right", "floor", "back", "ceiling"][self.index()]
    }
}

/// Tiles across and down in the window of a tiled CAVE.
pub const TILES: (u32, u32) = (3, 2);

/// A cube of six walls around the tracked head (the single-process view shows front, left,
/// right and floor).
#[derive(Clone, Copy, Debug)]
pub struct Cave {
    pub center: Vec3,
    pub half_size: f32,
    /// Unit horizontal direction the front wall faces the viewer from.
    pub forward: Vec3,
    /// The tracked head, relative to the centre in half-sizes: (right, up, back).
    pub head_offset: Vec3,
}

impl Cave {
    /// A CAVE where the scene's camera stands, facing the way it looks, with walls of `size`
    /// times the scene's diagonal. A camera outside the scene (e.g. the Cornell box's) walks
    /// along its view until the CAVE is inside the scene's bounds: the viewer steps in.
    pub fn placed(scene: &Scene, size: f32, head_offset: Vec3) -> Cave {
        let (lo, hi) = (scene.bounds_min, scene.bounds_max);
        let extent = (hi - lo).length().max(1e-3);
        let half_size = 0.5 * size * extent;
        let camera = &scene.camera;
        let look = (camera.target - camera.position).normalize_or(Vec3::NEG_Z);
        let forward = Vec3::new(look.x, 0.0, look.z).normalize_or(Vec3::NEG_Z);
        let inside = |p: Vec3| p.cmpge(lo).all() && p.cmple(hi).all();
        let center = if inside(camera.position) {
            camera.position
        } else {
            match entry_distance(camera.position, look, lo, hi) {
                Some(t) => camera.position + look * t + forward * (1.1 * half_size),
                None => 0.5 * (lo + hi),
            }
        };
        Cave {
            center,
            half_size,
            forward,
            head_offset,
        }
    }

    /// A CAVE placed as [`Cave::placed`] does, and the fly camera that carries it: standing at
    /// its centre, looking the way its front wall faces. The viewer and every render node of
    /// a cluster make their CAVE this way, so all of them draw the same walls.
    pub fn placed_with_fly(scene: &Scene, size: f32, head_offset: Vec3) -> (Cave, FlyCamera) {
        let extent = (scene.bounds_max - scene.bounds_min).length();
        let mut fly = FlyCamera::new(scene.camera, extent);
        let cave = Cave::placed(scene, size, head_offset);
        fly.camera.position = cave.center;
        fly.camera.target = cave.center + cave.forward;
        (cave, fly)
    }

    /// Carry the CAVE where `fly` stands, upright, facing the way it looks.
    pub fn follow(&mut self, fly: &FlyCamera) {
        self.center = fly.camera.position;
        self.forward = horizontal(fly.forward());
    }

    /// The walls in view order: front, left, right, floor (the single-process CAVE's).
    pub fn walls(&self) -> [Wall; 4] {
        let [front, left, right, floor, _, _] = self.all_walls();
        [front, left, right, floor]
    }

    /// The six walls of the cube, in [`WallName`] order: front, left, right, floor, back,
    /// ceiling.
    pub fn all_walls(&self) -> [Wall; 6] {
        let (c, h) = (self.center, self.half_size);
        let f = self.forward;
        let r = f.cross(Vec3::Y).normalize();
        let u = Vec3::Y;
        [
            Wall {
                name: WallName::Front.name(),
                corner: c + (f - r - u) * h,
                right: r * 2.0 * h,
                up: u * 2.0 * h,
            },
            Wall {
                name: WallName::Left.name(),
                corner: c + (-r - f - u) * h,
                right: f * 2.0 * h,
                up: u * 2.0 * h,
            },
            Wall {
                name: WallName::Right.name(),
                corner: c + (r + f - u) * h,
                right: -f * 2.0 * h,
                up: u * 2.0 * h,
            },
            Wall {
                name: WallName::Floor.name(),
                corner: c + (-u - r - f) * h,
                right: r * 2.0 * h,
                up: f * 2.0 * h,
            },
            Wall {
                name: WallName::Back.name(),
                corner: c + (r - f - u) * h,
                right: -r * 2.0 * h,
                up: u * 2.0 * h,
            },
            Wall {
                name: WallName::Ceiling.name(),
                corner: c + (u - r + f) * h,
                right: r * 2.0 * h,
                up: -f * 2.0 * h,
            },
        ]
    }

    /// The tracked head in world space.
    pub fn head(&self) -> Vec3 {
        let r = self.forward.cross(Vec3::Y).normalize();
        let o = self.head_offset * self.half_size;
        self.center + r * o.x + Vec3::Y * o.y - self.forward * o.z
    }

    /// One eye per wall, from the head, with clip planes enclosing the scene.
    pub fn eyes(&self, scene: &Scene) -> Vec<Eye> {
        self.walls()
            .iter()
            .map(|wall| self.eye(scene, wall))
            .collect()
    }

    /// The eye of the head looking through `wall`.
    pub fn eye(&self, scene: &Scene, wall: &Wall) -> Eye {
        self.eye_at(scene, wall, self.head())
    }

    /// The eyes of a stereo pair through `wall`, left then right: each `separation` (a
    /// fraction of the wall size) / 2 from the head along the CAVE's right axis (the viewer
    /// faces the front wall; the samples track no head rotation). Their frusta are off-axis
    /// through the same wall rectangle, so a point on the wall has no parallax.
    pub fn stereo_eyes(&self, scene: &Scene, wall: &Wall, separation: f32) -> [Eye; 2] {
        let r = self.forward.cross(Vec3::Y).normalize();
        let half = r * (0.5 * separation * 2.0 * self.half_size);
        let head = self.head();
        [head - half, head + half].map(|position| self.eye_at(scene, wall, position))
    }

    /// The eye at `position` looking through `wall`, with clip planes enclosing the scene.
    fn eye_at(&self, scene: &Scene, wall: &Wall, position: Vec3) -> Eye {
        let (lo, hi) = (scene.bounds_min, scene.bounds_max);
        let extent = (hi - lo).length().max(1e-3);
        let far = (0.5 * (lo + hi) - position).length() + extent;
        let near = (extent * 1e-3).min(far * 1e-3);
        Eye {
            view_projection: off_axis(position, wall, near, far),
            position,
        }
    }
}

/// Which eye (or eyes) a view shows.
#[derive(
    clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize,
)]
pub enum EyeChoice {
    /// One eye at the tracked head (no stereo).
    Mono,
    Left,
    Right,
    /// Both eyes, drawn from one frame pass (two eye passes).
    Both,
}

impl EyeChoice {
    pub fn name(self) -> &'static str {
        match self {
            EyeChoice::Mono => "mono",
            EyeChoice::Left => "left",
            EyeChoice::Right => "right",
            EyeChoice::Both => "both",
        }
    }

    /// Whether two nodes of one wall would show an eye twice (only a left and a right share).
    pub fn overlaps(self, other: EyeChoice) -> bool {
        !matches!(
            (self, other),
            (EyeChoice::Left, EyeChoice::Right) | (EyeChoice::Right, EyeChoice::Left)
        )
    }

    /// The eyes of `wall` this choice draws, in view order.
    pub fn eyes(self, cave: &Cave, scene: &Scene, wall: &Wall, separation: f32) -> Vec<Eye> {
        if self == EyeChoice::Mono {
            return vec![cave.eye(scene, wall)];
        }
        let [left, right] = cave.stereo_eyes(scene, wall, separation);
        match self {
            EyeChoice::Left => vec![left],
            EyeChoice::Right => vec![right],
            _ => vec![left, right],
        }
    }
}

/// A unit horizontal direction close to `v` (the CAVE stands upright).
fn horizontal(v: Vec3) -> Vec3 {
    Vec3::new(v.x, 0.0, v.z).normalize_or(Vec3::NEG_Z)
}

/// How far along `direction` a ray from `origin` enters the box `[lo, hi]`, if it does.
fn entry_distance(origin: Vec3, direction: Vec3, lo: Vec3, hi: Vec3) -> Option<f32> {
    let inv = direction.recip();
    let (a, b) = ((lo - origin) * inv, (hi - origin) * inv);
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element();
    (near <= far).then_some(near)
}

/// World-to-clip matrix (Vulkan: depth 0..1, y down) of the frustum from `eye` through
/// `wall`, clipped at `near` and `far`.
pub fn off_axis(eye: Vec3, wall: &Wall, near: f32, far: f32) -> Mat4 {
    let vr = wall.right.normalize();
    let vu = wall.up.normalize();
    let vn = vr.cross(vu).normalize();
    let va = wall.corner - eye;
    let vb = wall.corner + wall.right - eye;
    let vc = wall.corner + wall.up - eye;
    let distance = (-va.dot(vn)).max(1e-6);
    let scale = near / distance;
    let (l, r) = (vr.dot(va) * scale, vr.dot(vb) * scale);
    let (b, t) = (vu.dot(va) * scale, vu.dot(vc) * scale);
    let projection = Mat4::from_cols(
        Vec4::new(2.0 * near / (r - l), 0.0, 0.0, 0.0),
        Vec4::new(0.0, -2.0 * near / (t - b), 0.0, 0.0),
        Vec4::new(
            (r + l) / (r - l),
            -(t + b) / (t - b),
            far / (near - far),
            -1.0,
        ),
        Vec4::new(0.0, 0.0, near * far / (near - far), 0.0),
    );
    let rotation = Mat4::from_cols(
        Vec4::new(vr.x, vu.x, vn.x, 0.0),
        Vec4::new(vr.y, vu.y, vn.y, 0.0),
        Vec4::new(vr.z, vu.z, vn.z, 0.0),
        Vec4::W,
    );
    projection * rotation * Mat4::from_translation(-eye)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::camera::rh::{proj::vulkan, view::look_at_mat4};

    fn cave(head_offset: Vec3) -> Cave {
        Cave {
            center: Vec3::new(1.0, 2.0, 3.0),
            half_size: 0.5,
            forward: Vec3::NEG_Z,
            head_offset,
        }
    }

    #[test]
    fn centred_head_sees_the_front_wall_as_a_90_degree_camera() {
        let c = cave(Vec3::ZERO);
        let m = off_axis(c.head(), &c.walls()[0], 0.1, 50.0);
        let expected = vulkan::perspective(90f32.to_radians(), 1.0, 0.1, 50.0)
            * look_at_mat4(c.center, c.center + Vec3::NEG_Z, Vec3::Y);
        assert!(m.abs_diff_eq(expected, 1e-5), "{m} vs {expected}");
    }

    #[test]
    fn every_wall_maps_its_corners_to_the_image_corners_from_an_offset_head() {
        let c = cave(Vec3::new(0.3, -0.2, 0.4));
        for wall in c.all_walls() {
            let m = off_axis(c.head(), &wall, 0.01, 100.0);
            let ndc = |p: Vec3| {
                let clip = m * p.extend(1.0);
                clip.truncate() / clip.w
            };
            let lower_left = ndc(wall.corner);
            let upper_right = ndc(wall.corner + wall.right + wall.up);
            // Lower left of the wall is the image's bottom-left (Vulkan y down: +1).
            assert!(
                (lower_left.x + 1.0).abs() < 1e-4,
                "{}: {lower_left}",
                wall.name
            );
            assert!(
                (lower_left.y - 1.0).abs() < 1e-4,
                "{}: {lower_left}",
                wall.name
            );
            assert!(
                (upper_right.x - 1.0).abs() < 1e-4,
                "{}: {upper_right}",
                wall.name
            );
            assert!(
                (upper_right.y + 1.0).abs() < 1e-4,
                "{}: {upper_right}",
                wall.name
            );
            assert!((0.0..1.0).contains(&lower_left.z));
        }
    }

    #[test]
    fn edge_centred_walls_put_the_outer_pixel_centres_on_the_edges() {
        let c = cave(Vec3::new(0.3, -0.2, 0.4));
        let n = 48u32;
        for wall in c.all_walls() {
            let m = off_axis(c.head(), &wall.edge_centred(n), 0.01, 100.0);
            let pixel = |p: Vec3| {
                let clip = m * p.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                // Pixel coordinates whose centres are k + 0.5.
                (
                    (ndc.x + 1.0) * 0.5 * n as f32,
                    (ndc.y + 1.0) * 0.5 * n as f32,
                )
            };
            let (x0, y0) = pixel(wall.corner);
            let (x1, y1) = pixel(wall.corner + wall.right + wall.up);
            assert!(
                (x0 - 0.5).abs() < 1e-3 && (y0 - (n as f32 - 0.5)).abs() < 1e-3,
                "{}",
                wall.name
            );
            assert!(
                (x1 - (n as f32 - 0.5)).abs() < 1e-3 && (y1 - 0.5).abs() < 1e-3,
                "{}",
                wall.name
            );
        }
    }

    #[test]
    fn stereo_eyes_agree_on_the_wall_and_disagree_in_front_of_and_behind_it() {
        let scene = Scene::load("cornell").unwrap();
        let c = Cave {
            center: Vec3::new(0.28, 0.27, 0.28),
            ..cave(Vec3::new(0.2, 0.1, 0.3))
        };
        let ndc = |m: Mat4, p: Vec3| {
            let clip = m * p.extend(1.0);
            clip.truncate() / clip.w
        };
        for wall in c.all_walls() {
            let [left, right] = c.stereo_eyes(&scene, &wall, 0.05);
            assert!((left.position - right.position).length() > 0.04);
            let on_wall = wall.corner + 0.3 * wall.right + 0.6 * wall.up;
            let (a, b) = (
                ndc(left.view_projection, on_wall),
                ndc(right.view_projection, on_wall),
            );
            assert!(
                (a.x - b.x).abs() < 1e-4 && (a.y - b.y).abs() < 1e-4,
                "{}",
                wall.name
            );
            // A point beyond the wall shows parallax.
            let normal = wall.right.cross(wall.up).normalize();
            let beyond = on_wall - normal * 2.0;
            let (a, b) = (
                ndc(left.view_projection, beyond),
                ndc(right.view_projection, beyond),
            );
            assert!((a - b).length() > 1e-3, "{}: {a} {b}", wall.name);
        }
    }

    #[test]
    fn a_camera_outside_the_scene_steps_in_along_its_view() {
        let scene = Scene::load("cornell").unwrap();
        let cave = Cave::placed(&scene, 0.2, Vec3::ZERO);
        let (lo, hi) = (scene.bounds_min, scene.bounds_max);
        assert!(cave.center.cmpge(lo).all() && cave.center.cmple(hi).all());
        assert_eq!(cave.forward, Vec3::Z, "the Cornell camera looks down +z");
        let camera = scene.camera.position;
        assert!((cave.center.x - camera.x).abs() < 1e-3 && (cave.center.y - camera.y).abs() < 1e-3);
        assert!((cave.center.z - lo.z - 1.1 * cave.half_size).abs() < 1e-2);
        assert_eq!(
            entry_distance(Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::splat(2.0)),
            None
        );
    }

    #[test]
    fn adjacent_walls_share_their_edges() {
        let [front, left, right, floor] = cave(Vec3::ZERO).walls();
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        // front's left edge = left's right edge; front's right edge = right's left edge.
        assert!(close(front.corner, left.corner + left.right));
        assert!(close(front.corner + front.right, right.corner));
        // front's bottom edge = floor's top edge.
        assert!(close(front.corner, floor.corner + floor.up));
        assert!(close(
            front.corner + front.right,
            floor.corner + floor.up + floor.right
        ));
    }
}
