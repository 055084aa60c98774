//! LightWave's VPL rig (seed 002, spec 002 §2.2): virtual point lights at fixed places on
//! hemispherical shells around each light, opening along the light's axis, carried rigidly
//! with it. Rays run every `angle` degrees of azimuth and of tilt (tilts `angle`..90°, plus the
//! pole), with `per_ray` VPLs along each: VPL k of a ray sits at R (1 - 2^-(k+1)) from the light
//! (eq 4.1) and weighs 1 - 0.05·2^k (eq 4.2, 0-based as the thesis's code has it), and its
//! normal is the ray's direction. The positions ignore the geometry, as in the thesis.
//!
//! This is the f64 definition the GPU's generator (shaders-glsl/gi/lightwave/vpls.comp) is
//! tested against; the order of VPLs is the thesis's buffer order (pole ray first, then
//! azimuth-major, tilt, shell).

use glam::DVec3;

use crate::error::InputError;

/// Most VPLs per ray the thesis tried (Table 5.2); the sixth shell already weighs -0.6.
pub const MAX_PER_RAY: u32 = 6;
/// The tilt of the four outer VPLs of the integrated-shadow set (spec 002 §2.3).
const INTEGRATED_TILT_DEG: u32 = 30;

/// The shape of one light's rig.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rig {
    /// Degrees between neighbouring rays, in azimuth and in tilt; divides 90.
    pub angle_deg: u32,
    /// VPLs (shells) along each ray.
    pub per_ray: u32,
    /// maxDistance: the radius the shells converge to (scene units).
    pub radius: f64,
}

/// One VPL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vpl {
    pub position: DVec3,
    /// Unit direction away from the light (the axis of its emission lobe).
    pub direction: DVec3,
    /// 1 - attenuation of its shell.
    pub weight: f64,
}

impl Rig {
    pub fn new(angle_deg: u32, per_ray: u32, radius: f64) -> Result<Rig, InputError> {
        if angle_deg == 0 || 90 % angle_deg != 0 {
            return Err(InputError::new(format!(
                "--lightwave-angle {angle_deg}: the angle between rays must divide 90 (e.g. 5, 10, 30, 45, 90)"
            )));
        }
        if !(1..=MAX_PER_RAY).contains(&per_ray) {
            return Err(InputError::new(format!(
                "--lightwave-per-ray {per_ray}: out of range 1..={MAX_PER_RAY}"
            )));
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(InputError::new(format!(
                "--lightwave-radius {radius}: the rig's radius must be a positive number"
            )));
        }
        Ok(Rig {
            angle_deg,
            per_ray,
            radius,
        })
    }

    /// Tilts per azimuth (angle..90° in steps of angle).
    pub fn tilts(&self) -> u32 {
        90 / self.angle_deg
    }

    /// Azimuths (0..360° in steps of angle).
    pub fn azimuths(&self) -> u32 {
        360 / self.angle_deg
    }

    /// Rays: every (azimuth, tilt) and the pole (eq 5.1's bracket).
    pub fn rays(&self) -> u32 {
        self.tilts() * self.azimuths() + 1
    }

    /// VPLs per light (eq 5.1).
    pub fn count(&self) -> u32 {
        self.per_ray * self.rays()
    }

    /// Distance of shell `k` from the light (eq 4.1).
    pub fn shell_radius(&self, k: u32) -> f64 {
        self.radius * (1.0 - 0.5f64.powi(k as i32 + 1))
    }

    /// Weight of shell `k`: 1 - 0.05·2^k (eq 4.2), negative for k = 5.
    pub fn shell_weight(k: u32) -> f64 {
        1.0 - 0.05 * 2f64.powi(k as i32)
    }

    /// Ray `r`'s (tilt, azimuth) in degrees: ray 0 is the pole, then azimuth-major.
    pub fn ray_angles(&self, r: u32) -> (u32, u32) {
        if r == 0 {
            return (0, 0);
        }
        let (azimuth, tilt) = ((r - 1) / self.tilts(), (r - 1) % self.tilts());
        (self.angle_deg * (tilt + 1), self.angle_deg * azimuth)
    }

    /// VPL `j` of the rig of a light at `light` with unit `axis`.
    pub fn vpl(&self, light: DVec3, axis: DVec3, j: u32) -> Vpl {
        let (ray, k) = (j / self.per_ray, j % self.per_ray);
        let (tilt, azimuth) = self.ray_angles(ray);
        let (tilt, azimuth) = (f64::from(tilt).to_radians(), f64::from(azimuth).to_radians());
        let (u, w) = across(axis);
        let direction =
            axis * tilt.cos() + (u * azimuth.cos() + w * azimuth.sin()) * tilt.sin();
        Vpl {
            position: light + direction * self.shell_radius(k),
            direction,
            weight: Self::shell_weight(k),
        }
    }

    /// Every VPL of a light's rig, in buffer order.
    pub fn vpls(&self, light: DVec3, axis: DVec3) -> Vec<Vpl> {
        (0..self.count()).map(|j| self.vpl(light, axis, j)).collect()
    }

    /// The thesis's "accurate shadows" set: `k` VPLs drawn as `rand() % N` from the C runtime
    /// its code ran on (MSVC's generator, unseeded, i.e. seed 1), so the same VPLs cast shadows
    /// as in its results (spec 002 §2.3; repeats are kept, as there).
    pub fn accurate_shadow_set(&self, k: u32) -> Vec<u32> {
        let mut state: u32 = 1;
        (0..k)
            .map(|_| {
                state = state.wrapping_mul(214_013).wrapping_add(2_531_011);
                ((state >> 16) & 0x7fff) % self.count()
            })
            .collect()
    }

    /// The thesis's "integrated shadows" set: the pole VPL and the innermost VPL of the four
    /// rays at azimuth 0°, 90°, 180°, 270° and the tilt nearest 30° (exactly 30° when the angle
    /// divides 30).
    pub fn integrated_shadow_set(&self) -> [u32; 5] {
        let tilt = (1..=self.tilts())
            .min_by_key(|t| (t * self.angle_deg).abs_diff(INTEGRATED_TILT_DEG))
            .unwrap_or(1)
            - 1;
        let quarter = self.azimuths() / 4;
        let ray = |azimuth: u32| 1 + azimuth * self.tilts() + tilt;
        [
            0,
            ray(0) * self.per_ray,
            ray(quarter) * self.per_ray,
            ray(2 * quarter) * self.per_ray,
            ray(3 * quarter) * self.per_ray,
        ]
    }
}

/// Two unit vectors across `axis` (u, w): the frame of src/scene/gpu.rs `light_frame` in f64,
/// with its second vector negated, so that a light looking down (-y) gets the thesis's closed
/// form n = (sin t cos a, -cos t, -sin t sin a) as n = axis cos t + (u cos a + w sin a) sin t.
pub fn across(axis: DVec3) -> (DVec3, DVec3) {
    let up = if axis.y.abs() > 0.9 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let u = up.cross(axis).normalize();
    (u, u.cross(axis))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn thesis() -> Rig {
        Rig::new(5, 5, 4.0).expect("the thesis's rig")
    }

    #[test]
    fn vpl_counts_follow_eq_5_1() {
        assert_eq!(thesis().count(), 6485);
        for (angle, count) in [(10, 1625), (30, 185), (45, 85), (90, 25)] {
            assert_eq!(Rig::new(angle, 5, 4.0).map(|r| r.count()).ok(), Some(count));
        }
        for (per_ray, count) in [(1, 1297), (2, 2594), (3, 3891), (4, 5188), (6, 7782)] {
            assert_eq!(Rig::new(5, per_ray, 4.0).map(|r| r.count()).ok(), Some(count));
        }
        for bad in [(0, 5), (7, 5), (60, 5), (5, 0), (5, 7)] {
            assert!(Rig::new(bad.0, bad.1, 4.0).is_err(), "{bad:?}");
        }
        assert!(Rig::new(5, 5, 0.0).is_err() && Rig::new(5, 5, f64::NAN).is_err());
    }

    #[test]
    fn shells_and_weights_are_the_thesis_values() {
        let rig = thesis();
        let radii: Vec<f64> = (0..5).map(|k| rig.shell_radius(k)).collect();
        assert_eq!(radii, [2.0, 3.0, 3.5, 3.75, 3.875]);
        let weights: Vec<f64> = (0..6).map(Rig::shell_weight).collect();
        for (w, want) in weights.iter().zip([0.95, 0.9, 0.8, 0.6, 0.2, -0.6]) {
            assert!((w - want).abs() < 1e-12, "{w} {want}");
        }
    }

    #[test]
    fn a_light_looking_down_gives_the_closed_form_directions() {
        let rig = thesis();
        let light = DVec3::new(0.0, 3.9, 3.0);
        let vpls = rig.vpls(light, DVec3::NEG_Y);
        for (j, vpl) in vpls.iter().enumerate() {
            let j = j as u32;
            let (tilt, azimuth) = rig.ray_angles(j / 5);
            let (t, a) = (f64::from(tilt).to_radians(), f64::from(azimuth).to_radians());
            let want = DVec3::new(t.sin() * a.cos(), -t.cos(), -t.sin() * a.sin());
            assert!((vpl.direction - want).length() < 1e-12, "VPL {j}");
            let distance = (vpl.position - light).length();
            assert!((distance - rig.shell_radius(j % 5)).abs() < 1e-12, "VPL {j}");
        }
        // Index formula of spec 002 §2.2: perRay + ((aY/A)(90/A) + (aZ/A - 1)) perRay + k.
        let (ay, az, k) = (35u32, 60u32, 3u32);
        let index = 5 + ((ay / 5) * 18 + (az / 5 - 1)) * 5 + k;
        assert_eq!(rig.ray_angles(index / 5), (az, ay));
        // Every position is distinct.
        for (i, a) in vpls.iter().enumerate().step_by(97) {
            for b in &vpls[i + 1..] {
                assert!((a.position - b.position).length() > 1e-6);
            }
        }
    }

    #[test]
    fn the_rig_moves_and_turns_rigidly_with_its_light() {
        let rig = thesis();
        let here = rig.vpls(DVec3::ZERO, DVec3::NEG_Y);
        let moved = rig.vpls(DVec3::new(1.0, -2.0, 0.5), DVec3::NEG_Y);
        for (a, b) in here.iter().zip(&moved) {
            assert!((b.position - a.position - DVec3::new(1.0, -2.0, 0.5)).length() < 1e-12);
            assert_eq!(a.direction, b.direction);
        }
        // Aimed along +x: every VPL keeps its distance and its angle to the axis.
        let aimed = rig.vpls(DVec3::ZERO, DVec3::X);
        for (a, b) in here.iter().zip(&aimed) {
            assert!((a.position.length() - b.position.length()).abs() < 1e-12);
            assert!((a.direction.dot(DVec3::NEG_Y) - b.direction.dot(DVec3::X)).abs() < 1e-12);
        }
    }

    #[test]
    fn shadow_sets_are_the_thesis_indices() {
        let rig = thesis();
        let accurate = [
            41, 5497, 6334, 560, 6199, 2754, 4993, 3418, 1022, 5009, 5705, 2205, 3826, 3857,
            3476, 491, 2995, 5457, 4827, 5436,
        ];
        assert_eq!(rig.accurate_shadow_set(20), accurate);
        assert_eq!(rig.integrated_shadow_set(), [0, 30, 1650, 3270, 4890]);
        let coarse = Rig::new(30, 5, 4.0).expect("rig");
        assert_eq!(coarse.integrated_shadow_set(), [0, 5, 50, 95, 140]);
        // With the light at (0, 4, 0) the four outer ones sit at (±1, 2.268, 0), (0, 2.268, ±1).
        let light = DVec3::new(0.0, 4.0, 0.0);
        for j in &rig.integrated_shadow_set()[1..] {
            let p = rig.vpl(light, DVec3::NEG_Y, *j).position;
            assert!((p.y - (4.0 - 3f64.sqrt())).abs() < 1e-12, "{p}");
            assert!(((p.x.abs() + p.z.abs()) - 1.0).abs() < 1e-12, "{p}");
        }
    }
}
