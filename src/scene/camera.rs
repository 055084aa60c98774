//! A pinhole camera. Raster and path tracer derive their rays and matrices from this alone, so
//! their images line up pixel for pixel.

use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, Vec2, Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub vfov_deg: f32,
}

impl Camera {
    /// A camera that sees the whole box `[min, max]` from the front (+z), slightly above.
    pub fn framing(min: Vec3, max: Vec3) -> Camera {
        let center = 0.5 * (min + max);
        let radius = (0.5 * (max - min).length()).max(1e-3);
        let vfov_deg: f32 = 45.0;
        let distance = radius / (0.5 * vfov_deg.to_radians()).sin();
        Camera {
            position: center + Vec3::new(0.0, 0.25, 1.0).normalize() * distance,
            target: center,
            up: Vec3::Y,
            vfov_deg,
        }
    }

    pub fn view(&self) -> Mat4 {
        look_at_mat4(self.position, self.target, self.up)
    }

    /// Vulkan projection: depth 0..1, y down in normalised device coordinates.
    pub fn projection(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        vulkan::perspective(self.vfov_deg.to_radians(), aspect, near, far)
    }

    /// Near and far planes that enclose a scene of the given bounds.
    pub fn clip_planes(&self, min: Vec3, max: Vec3) -> (f32, f32) {
        let center = 0.5 * (min + max);
        let radius = 0.5 * (max - min).length();
        let distance = (center - self.position).length();
        let far = (distance + radius) * 1.01 + 1e-3;
        let near = (far * 1e-4).max(distance - radius).max(far * 1e-4);
        (near.min(far * 0.5), far)
    }

    /// World-to-clip matrix for an image of the given aspect ratio.
    pub fn view_projection(&self, aspect: f32, min: Vec3, max: Vec3) -> Mat4 {
        let (near, far) = self.clip_planes(min, max);
        self.projection(aspect, near, far) * self.view()
    }

    /// Unit direction of the ray through image point `pixel` (pixel units, (0,0) = top-left
    /// corner of the image; a pixel centre is at +0.5).
    pub fn ray_direction(&self, pixel: Vec2, width: u32, height: u32) -> Vec3 {
        let ndc = Vec2::new(
            2.0 * pixel.x / width as f32 - 1.0,
            2.0 * pixel.y / height as f32 - 1.0,
        );
        let aspect = width as f32 / height as f32;
        let inv = (self.projection(aspect, 0.1, 10.0) * self.view()).inverse();
        let near = inv * Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - near.truncate() / near.w).normalize()
    }

    /// Pixel coordinates (fractional, top-left origin) where a world point lands, if in front.
    pub fn project(&self, point: Vec3, width: u32, height: u32) -> Option<Vec2> {
        let aspect = width as f32 / height as f32;
        let clip = self.projection(aspect, 0.1, 10.0) * self.view() * point.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * width as f32,
            (ndc.y + 1.0) * 0.5 * height as f32,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_and_ray_agree() {
        let cam = Camera {
            position: Vec3::new(1.0, 2.0, -5.0),
            target: Vec3::new(0.5, 1.0, 0.0),
            up: Vec3::Y,
            vfov_deg: 40.0,
        };
        let p = Vec3::new(0.3, 1.7, 0.8);
        let px = cam.project(p, 640, 480).unwrap();
        let dir = cam.ray_direction(px, 640, 480);
        let expected = (p - cam.position).normalize();
        assert!(dir.dot(expected) > 0.999_999, "{dir} vs {expected}");
    }

    #[test]
    fn image_top_is_world_up() {
        let cam = Camera {
            position: Vec3::ZERO,
            target: Vec3::Z,
            up: Vec3::Y,
            vfov_deg: 60.0,
        };
        let above = cam.project(Vec3::new(0.0, 1.0, 5.0), 100, 100).unwrap();
        assert!(
            above.y < 50.0,
            "points above the axis land in the upper half: {above}"
        );
        let left = cam.project(Vec3::new(1.0, 0.0, 5.0), 100, 100).unwrap();
        assert!(
            left.x < 50.0,
            "+x is to the left when looking down +z with +y up: {left}"
        );
    }
}
