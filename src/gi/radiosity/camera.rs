//! The user's camera as the id and pd modes see it (spec 004 §5, §6.1): the world-to-clip
//! transform, the eye and the axis, and the same camera with a wider simulated field of view
//! (the displayed view is unchanged; only the test of which surfaces are in view widens).

use glam::{Mat4, Vec3, Vec4};

use crate::render::targets::Eye;

/// The widest simulated field of view: the projection holds cot(fov / 2), so 180° is out of
/// reach (spec 004 §6.1); at this width everything in front of the eye is in view.
pub const MAX_FOV_DEG: f32 = 179.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// World to clip (Vulkan: depth 0..1).
    pub clip: Mat4,
    pub eye: Vec3,
    /// Unit axis the camera looks along.
    pub forward: Vec3,
}

impl CameraView {
    /// The camera of a view whose projection is a symmetric perspective one.
    pub fn of(eye: &Eye) -> CameraView {
        // The clip w row of a perspective projection is the view's depth axis.
        let w_row = eye.view_projection.row(3).truncate();
        CameraView {
            clip: eye.view_projection,
            eye: eye.position,
            forward: w_row.normalize_or(Vec3::NEG_Z),
        }
    }

    /// Vertical field of view in degrees: the clip y row's length is cot(fov / 2).
    pub fn vertical_fov_deg(&self) -> f32 {
        let cot = self.clip.row(1).truncate().length().max(1e-6);
        (2.0 * (1.0 / cot).atan()).to_degrees()
    }

    /// The same camera with vertical field of view `fov_deg` (clamped to [`MAX_FOV_DEG`]),
    /// the horizontal one widened in proportion (the aspect kept).
    pub fn widened(&self, fov_deg: f32) -> CameraView {
        let now = (0.5 * self.vertical_fov_deg().to_radians()).tan();
        let wide = (0.5 * fov_deg.min(MAX_FOV_DEG).to_radians()).tan();
        let scale = now / wide;
        let squeeze = Mat4::from_diagonal(Vec4::new(scale, scale, 1.0, 1.0));
        CameraView {
            clip: squeeze * self.clip,
            ..*self
        }
    }
}

/// The simulated field of view widens by this much at each decay (spec 004 App. A).
pub const FOV_STEP_DEG: f32 = 5.0;

/// pd's simulated field of view (spec 004 §6.1): the user's on a camera change, then 5° wider
/// after every `decay_shots` shots, up to [`MAX_FOV_DEG`]; one decay later every surface counts
/// as in view (the spec's optional flush: surfaces behind the eye or hidden from it would
/// otherwise never receive, and the solution never converge). `generation` counts its changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatedView {
    pub fov_deg: f32,
    /// Every surface is in view (after the widest field of view).
    pub everything: bool,
    pub generation: u32,
    decay_shots: u32,
    shots: u32,
}

impl SimulatedView {
    pub fn new(decay_shots: u32) -> SimulatedView {
        SimulatedView {
            fov_deg: 0.0,
            everything: false,
            generation: 0,
            decay_shots: decay_shots.max(1),
            shots: 0,
        }
    }

    /// A new area of interest: back to the user's field of view.
    pub fn reset(&mut self, user_fov_deg: f32) {
        self.fov_deg = user_fov_deg.min(MAX_FOV_DEG);
        self.everything = false;
        self.shots = 0;
        self.generation += 1;
    }

    /// One more shot; whether the view widened (decayed) with it.
    pub fn count_shot(&mut self) -> bool {
        self.shots += 1;
        if self.shots < self.decay_shots || self.saturated() {
            return false;
        }
        self.shots = 0;
        if self.fov_deg >= MAX_FOV_DEG {
            self.everything = true;
        }
        self.fov_deg = (self.fov_deg + FOV_STEP_DEG).min(MAX_FOV_DEG);
        self.generation += 1;
        true
    }

    /// Every surface in view: no decay will change it any more.
    pub fn saturated(&self) -> bool {
        self.everything
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    #[test]
    fn the_field_of_view_is_read_back_and_widened() {
        let camera = Camera {
            position: Vec3::new(0.0, 1.0, 5.0),
            target: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            vfov_deg: 40.0,
        };
        let eye = Eye {
            view_projection: camera.view_projection(1.5, Vec3::splat(-2.0), Vec3::splat(2.0)),
            position: camera.position,
        };
        let view = CameraView::of(&eye);
        assert!((view.vertical_fov_deg() - 40.0).abs() < 1e-3);
        assert!((view.forward - Vec3::NEG_Z).length() < 1e-5, "{}", view.forward);
        let wide = view.widened(90.0);
        assert!((wide.vertical_fov_deg() - 90.0).abs() < 1e-3);
        // A point 44° above the axis is outside 40° and inside 90°.
        let p = Vec3::new(0.0, 1.0 + 5.0 * 44f32.to_radians().tan(), 0.0);
        let inside = |v: &CameraView| {
            let c = v.clip * p.extend(1.0);
            c.y.abs() <= c.w
        };
        assert!(!inside(&view) && !inside(&view.widened(80.0)) && inside(&wide));
        assert_eq!(view.widened(400.0).vertical_fov_deg().round(), MAX_FOV_DEG);
    }

    #[test]
    fn the_simulated_view_widens_every_decay_and_resets() {
        let mut view = SimulatedView::new(3);
        view.reset(170.0);
        assert_eq!(view.generation, 1);
        let widened: Vec<bool> = (0..12).map(|_| view.count_shot()).collect();
        let changes = [false, false, true, false, false, true, false, false, true];
        assert_eq!(widened[..9], changes);
        assert_eq!(widened[9..], [false; 3]);
        assert_eq!((view.fov_deg, view.generation), (MAX_FOV_DEG, 4));
        assert!(view.saturated() && view.everything);
        view.reset(10.0);
        assert_eq!((view.fov_deg, view.generation, view.everything), (10.0, 5, false));
    }
}
