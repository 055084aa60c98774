//! Punctual lights. The spot profile and the flux-to-intensity conversion defined here are the
//! single definition the rasteriser, the path tracer and the tests all use.

use glam::Vec3;

/// Widest spot cone (half-angle, degrees) one perspective shadow view covers; wider spots, up
/// to the 90° hemisphere, use five views.
pub const WIDE_SPOT_DEG: f32 = 60.0;

/// Widest spot cone (half-angle, degrees): a uniform hemisphere.
pub const MAX_CONE_DEG: f32 = 90.0;

/// Narrowest spot cone (half-angle, degrees): narrower cones' solid angles fall below f32's
/// resolution of the flux-to-intensity division (the fuzzing pass found a cone of 1e-45
/// radians giving a NaN intensity).
pub const MIN_CONE_DEG: f32 = 0.01;

/// The shape of a light's emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// A spot light: full intensity inside `cone_angle - penumbra` of the axis, falling off as
    /// ((cos θ - cos θ_outer) / (cos θ_inner - cos θ_outer))² to zero at `cone_angle`
    /// (the D3D-style profile of seed 000, with exponent 2).
    Spot {
        direction: Vec3,
        /// Half-angle from the axis to the edge of the cone, degrees.
        cone_angle_deg: f32,
        /// Width of the soft edge inside the cone, degrees.
        penumbra_deg: f32,
    },
    /// Emits the same intensity in every direction.
    Point,
    /// A Lambertian patch: intensity ∝ cos θ over the hemisphere around `direction` (a sample
    /// of an area light, as the rasteriser and RSM-based methods see it).
    Cosine { direction: Vec3 },
}

/// Shadow (and RSM) views all of `lights` need together; at least one, so a layered image
/// for them is never empty.
pub fn shadow_view_total(lights: &[Light]) -> u32 {
    lights
        .iter()
        .map(Light::shadow_view_count)
        .sum::<u32>()
        .max(1)
}

/// A punctual light with total emitted flux `flux` watts, tinted by `color` per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    pub kind: LightKind,
    pub flux: f32,
    pub color: Vec3,
}

impl Light {
    /// Shadow (and RSM) views the light needs: one per spot light up to [`WIDE_SPOT_DEG`],
    /// five (the faces of a cube around its axis but the back one) for a wider spot, six (cube
    /// faces) per point light.
    pub fn shadow_view_count(&self) -> u32 {
        match self.kind {
            LightKind::Spot { cone_angle_deg, .. } if cone_angle_deg > WIDE_SPOT_DEG => 5,
            LightKind::Spot { .. } => 1,
            LightKind::Cosine { .. } => 5,
            LightKind::Point => 6,
        }
    }

    /// cos of the outer (zero) and inner (full) cone angles; (-1, -1) for a point light.
    pub fn cone_cosines(&self) -> (f32, f32) {
        match self.kind {
            LightKind::Spot {
                cone_angle_deg,
                penumbra_deg,
                ..
            } => {
                let outer = cone_angle_deg.to_radians();
                let inner = (cone_angle_deg - penumbra_deg).max(0.0).to_radians();
                (outer.cos(), inner.cos())
            }
            LightKind::Point | LightKind::Cosine { .. } => (-1.0, -1.0),
        }
    }

    /// Relative intensity toward unit direction `to_point` (from the light), in [0, 1].
    pub fn profile(&self, to_point: Vec3) -> f32 {
        match self.kind {
            LightKind::Point => 1.0,
            LightKind::Spot { direction, .. } => {
                let (cos_outer, cos_inner) = self.cone_cosines();
                spot_profile(direction.normalize().dot(to_point), cos_outer, cos_inner)
            }
            LightKind::Cosine { direction } => direction.dot(to_point).max(0.0),
        }
    }

    /// The light's axis (spot and cosine lights), or None for a point light.
    pub fn axis(&self) -> Option<Vec3> {
        match self.kind {
            LightKind::Spot { direction, .. } | LightKind::Cosine { direction } => Some(direction),
            LightKind::Point => None,
        }
    }

    /// Solid angle the profile integrates to (sr): the light's intensity is flux / this.
    pub fn profile_solid_angle(&self) -> f32 {
        match self.kind {
            LightKind::Point => 4.0 * std::f32::consts::PI,
            LightKind::Spot { .. } => {
                let (cos_outer, cos_inner) = self.cone_cosines();
                // 2π [ ∫_{cos_inner}^{1} 1 dc + ∫_{cos_outer}^{cos_inner} ((c-co)/(ci-co))² dc ]
                2.0 * std::f32::consts::PI * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 3.0)
            }
            // ∫ max(0, cos θ) dω over the sphere.
            LightKind::Cosine { .. } => std::f32::consts::PI,
        }
    }

    /// Peak radiant intensity per channel, W/sr, such that the emitted flux is `flux * color`.
    pub fn intensity(&self) -> Vec3 {
        self.color * (self.flux / self.profile_solid_angle())
    }

    /// Irradiance (W/m² per channel) this light delivers, unoccluded, to a surface at `point`
    /// with unit normal `normal`.
    pub fn irradiance_at(&self, point: Vec3, normal: Vec3) -> Vec3 {
        let to_point = point - self.position;
        let distance_sq = to_point.length_squared();
        if distance_sq <= 0.0 {
            return Vec3::ZERO;
        }
        let dir = to_point / distance_sq.sqrt();
        let cos_surface = normal.dot(-dir).max(0.0);
        self.intensity() * (self.profile(dir) * cos_surface / distance_sq)
    }
}

/// The spot falloff: 0 outside `cos_outer`, 1 inside `cos_inner`, quadratic in between.
pub fn spot_profile(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_angle <= cos_outer {
        0.0
    } else if cos_angle >= cos_inner {
        1.0
    } else {
        let t = (cos_angle - cos_outer) / (cos_inner - cos_outer).max(1e-9);
        t * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(cone: f32, penumbra: f32) -> Light {
        Light {
            position: Vec3::ZERO,
            kind: LightKind::Spot {
                direction: Vec3::NEG_Y,
                cone_angle_deg: cone,
                penumbra_deg: penumbra,
            },
            flux: 10.0,
            color: Vec3::ONE,
        }
    }

    /// Integrate the profile over the sphere numerically: flux out must equal flux in.
    #[test]
    fn spot_emits_exactly_its_flux() {
        for (cone, penumbra) in [(30.0, 5.0), (60.0, 10.0), (45.0, 45.0), (80.0, 0.0)] {
            let light = spot(cone, penumbra);
            let n = 200_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                // Midpoint rule over cos θ in [-1, 1] (the profile is axially symmetric).
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let s = (1.0 - c * c).sqrt();
                let dir = Vec3::new(s as f32, -(c as f32), 0.0);
                sum += f64::from(light.profile(dir));
            }
            let omega = 2.0 * std::f64::consts::PI * sum * 2.0 / n as f64;
            let emitted = f64::from(light.intensity().x) * omega;
            assert!(
                (emitted - 10.0).abs() < 1e-3 * 10.0,
                "cone {cone}: {emitted}"
            );
        }
    }

    #[test]
    fn point_light_irradiance_is_inverse_square_cosine() {
        let light = Light {
            position: Vec3::new(0.0, 2.0, 0.0),
            kind: LightKind::Point,
            flux: 4.0 * std::f32::consts::PI,
            color: Vec3::ONE,
        };
        let e = light.irradiance_at(Vec3::new(2.0, 0.0, 0.0), Vec3::Y);
        // I = 1 W/sr, r² = 8, cos = 1/√2.
        assert!((e.x - (1.0 / 8.0) * std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    }

    #[test]
    fn profile_is_continuous_at_both_edges() {
        let (co, ci) = (0.5, 0.6);
        assert_eq!(spot_profile(0.5, co, ci), 0.0);
        assert!(spot_profile(0.50001, co, ci) < 1e-6);
        assert!((spot_profile(0.5999, co, ci) - 1.0).abs() < 3e-3);
        assert_eq!(spot_profile(0.6, co, ci), 1.0);
    }
}
