//! What the master makes of its input each frame: the tracked sample (a `--path` line, or the
//! fixed `--head`), moved further by the keys held and the mouse dragged in its window (or by
//! `--keys`, one scripted key per frame). Steps are per frame, not per second, so a scripted
//! run gives the same poses on every machine.

use glam::Vec3;
use winit::keyboard::KeyCode;

use super::Pose;
use super::path::TrackedPath;
use crate::view::keys;

/// Head travel per frame a key is held, in half wall sizes.
const HEAD_STEP: f32 = 0.02;
/// Head travel per pixel dragged, in half wall sizes.
const HEAD_PER_PIXEL: f32 = 0.005;
/// Light travel per frame a key is held, as a fraction of the scene's diagonal.
const LIGHT_STEP: f32 = 0.005;

/// The master's keys, for its overlay.
pub const HELP: &str = "WASD QE DRAG  HEAD    ARROWS PGUP PGDN  LIGHT    ESC  STOP";

pub struct Input {
    path: Option<TrackedPath>,
    head: Vec3,
    /// Where the scene put its first light (None: it has none).
    scene_light: Option<Vec3>,
    light_step: f32,
    /// What the keys and the mouse added so far.
    head_offset: Vec3,
    light_offset: Vec3,
}

impl Input {
    pub fn new(
        path: Option<TrackedPath>,
        head: Vec3,
        scene_light: Option<Vec3>,
        scene_diagonal: f32,
    ) -> Input {
        Input {
            path,
            head,
            scene_light,
            light_step: LIGHT_STEP * scene_diagonal,
            head_offset: Vec3::ZERO,
            light_offset: Vec3::ZERO,
        }
    }

    /// The pose of frame `frame`, after `held` keys and a drag of `dragged` pixels.
    pub fn pose(&mut self, frame: u64, held: &[KeyCode], dragged: (f32, f32)) -> Pose {
        let pressed = |key: KeyCode| held.contains(&key);
        let axis = |plus, minus| keys::axis(&pressed, plus, minus);
        let sample = match &self.path {
            Some(path) => path.at(frame),
            None => Pose {
                head: self.head,
                light: None,
            },
        };
        self.head_offset += HEAD_STEP
            * Vec3::new(
                axis(KeyCode::KeyD, KeyCode::KeyA),
                axis(KeyCode::KeyE, KeyCode::KeyQ),
                axis(KeyCode::KeyS, KeyCode::KeyW),
            )
            + HEAD_PER_PIXEL * Vec3::new(dragged.0, -dragged.1, 0.0);
        // The head stays inside the CAVE.
        let head = (sample.head + self.head_offset).clamp(Vec3::splat(-1.0), Vec3::ONE);
        self.head_offset = head - sample.head;
        let moved = keys::light_motion(&pressed);
        let light = sample.light.or(self.scene_light).and_then(|base| {
            self.light_offset += moved * self.light_step;
            // Untouched, a path without lights leaves the light where the scene put it.
            (sample.light.is_some() || self.light_offset != Vec3::ZERO)
                .then_some(base + self.light_offset)
        });
        Pose { head, light }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_and_drags_move_the_head_and_light_from_the_sample() {
        let mut input = Input::new(None, Vec3::new(0.2, 0.1, 0.3), Some(Vec3::ONE), 2.0);
        let still = input.pose(0, &[], (0.0, 0.0));
        assert_eq!(still.head, Vec3::new(0.2, 0.1, 0.3));
        assert_eq!(still.light, None, "an untouched light stays the scene's");
        let moved = input.pose(1, &[KeyCode::KeyD, KeyCode::ArrowRight], (10.0, 0.0));
        assert!((moved.head.x - (0.2 + HEAD_STEP + 10.0 * HEAD_PER_PIXEL)).abs() < 1e-6);
        assert_eq!(
            moved.light,
            Some(Vec3::new(1.0 + 2.0 * LIGHT_STEP, 1.0, 1.0))
        );
        // The offsets persist once the keys let go.
        assert_eq!(input.pose(2, &[], (0.0, 0.0)), moved);
    }

    #[test]
    fn the_head_cannot_leave_the_cave() {
        let mut input = Input::new(None, Vec3::new(0.99, 0.0, 0.0), None, 1.0);
        for frame in 0..10 {
            input.pose(frame, &[KeyCode::KeyD], (0.0, 0.0));
        }
        assert_eq!(input.pose(10, &[], (0.0, 0.0)).head.x, 1.0);
        // Back off the wall at once (no hidden overshoot to undo first).
        assert!(input.pose(11, &[KeyCode::KeyA], (0.0, 0.0)).head.x < 1.0);
    }

    #[test]
    fn a_path_drives_the_pose_and_keys_add_to_it() {
        let path = TrackedPath::parse("0 0 0 1 1 1\n0.5 0 0 2 2 2\n").unwrap();
        let mut input = Input::new(Some(path), Vec3::ZERO, Some(Vec3::ZERO), 1.0);
        assert_eq!(input.pose(0, &[], (0.0, 0.0)).light, Some(Vec3::ONE));
        let second = input.pose(1, &[KeyCode::PageUp], (0.0, 0.0));
        assert_eq!(second.head, Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(second.light, Some(Vec3::new(2.0, 2.0 + LIGHT_STEP, 2.0)));
    }
}
