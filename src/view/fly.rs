//! A fly camera: WASD moves along the view, a mouse drag turns it, the wheel sets the speed.

use glam::Vec3;

use crate::scene::Camera;

/// Steepest pitch the camera turns to, short of straight up or down (degrees).
const MAX_PITCH_DEG: f32 = 89.0;
/// Radians turned per pixel of mouse drag.
const RADIANS_PER_PIXEL: f32 = 0.004;
/// Speed factor per scroll-wheel step.
const SPEED_STEP: f32 = 1.25;

#[derive(Clone, Debug)]
pub struct FlyCamera {
    /// The camera as the user left it: unchanged until they move it, so an unmoved view
    /// matches a headless render of the scene's camera exactly.
    pub camera: Camera,
    /// Scene units per second.
    pub speed: f32,
}

impl FlyCamera {
    /// Start at `camera`, crossing the scene (of diagonal `extent`) in about four seconds.
    pub fn new(camera: Camera, extent: f32) -> FlyCamera {
        FlyCamera {
            camera,
            speed: 0.25 * extent.max(1e-3),
        }
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        (self.camera.target - self.camera.position).normalize_or(Vec3::NEG_Z)
    }

    /// Unit direction to the right of the view, in the horizontal plane.
    pub fn right(&self) -> Vec3 {
        self.forward().cross(Vec3::Y).normalize_or(Vec3::X)
    }

    /// Move by `local` (x right, y up, z forward; each -1..1) for `seconds`.
    pub fn travel(&mut self, local: Vec3, seconds: f32) {
        if local == Vec3::ZERO {
            return;
        }
        let step = (self.right() * local.x + Vec3::Y * local.y + self.forward() * local.z)
            * self.speed
            * seconds;
        self.camera.position += step;
        self.camera.target += step;
    }

    /// Turn by a mouse drag of (dx, dy) pixels (right and down positive).
    pub fn turn(&mut self, dx: f32, dy: f32) {
        let forward = self.forward();
        let mut yaw = forward.x.atan2(-forward.z);
        let mut pitch = forward.y.clamp(-1.0, 1.0).asin();
        yaw += dx * RADIANS_PER_PIXEL;
        let limit = MAX_PITCH_DEG.to_radians();
        pitch = (pitch - dy * RADIANS_PER_PIXEL).clamp(-limit, limit);
        let direction = Vec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            -pitch.cos() * yaw.cos(),
        );
        let distance = (self.camera.target - self.camera.position)
            .length()
            .max(1e-3);
        self.camera.target = self.camera.position + direction * distance;
        self.camera.up = Vec3::Y;
    }

    /// Scroll-wheel steps: each makes the camera 25% faster (up) or slower (down).
    pub fn scroll(&mut self, steps: f32) {
        self.speed = (self.speed * SPEED_STEP.powf(steps)).clamp(1e-6, 1e6);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(1.0, 2.0, 0.0),
            up: Vec3::Y,
            vfov_deg: 40.0,
        }
    }

    #[test]
    fn travelling_forward_moves_along_the_view() {
        let mut fly = FlyCamera::new(camera(), 4.0);
        fly.travel(Vec3::Z, 2.0);
        assert!((fly.camera.position - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-6);
        assert_eq!(fly.forward(), Vec3::NEG_Z);
    }

    #[test]
    fn turning_right_then_left_returns_and_pitch_stops_short_of_the_pole() {
        let mut fly = FlyCamera::new(camera(), 4.0);
        fly.turn(100.0, 0.0);
        assert!(fly.forward().x > 0.3, "dragging right turns right");
        fly.turn(-100.0, 0.0);
        assert!((fly.forward() - Vec3::NEG_Z).length() < 1e-5);
        fly.turn(0.0, -1e6);
        assert!(fly.forward().y < 1.0 && fly.forward().y > 0.99);
    }

    #[test]
    fn scrolling_changes_speed_geometrically() {
        let mut fly = FlyCamera::new(camera(), 4.0);
        fly.scroll(2.0);
        assert!((fly.speed - 1.5625).abs() < 1e-5);
    }
}
