//! The half-resolution lookup's upsample (`--lookup-resolution half`) in f64, the reference the
//! GPU's `lpv/upsample.glsl` and `lpv/half_light.glsl` are tested against (without the texels'
//! half-float and snorm16 rounding): texel (i, j) of the quarter-size image holds the light per
//! unit albedo at the surface of full-resolution pixel (2i, 2j), with that surface's distance
//! from the eye and its normal; a full-resolution pixel takes the four texels around it, each
//! weighted bilinearly, by a tent of their distances' difference times the cosine between the
//! pixel's normal and its ray (at least [`MIN_FACING`]; about the texel's distance from the
//! pixel's plane, so that a surface seen at a grazing angle keeps its neighbours), zero at
//! [`DISTANCE_TOLERANCE`] of the pixel's distance, and by the normals' cosine to the eighth;
//! where the weights sum below [`LEAST_WEIGHT`], the most alike texel's light (the first of
//! those within [`MISS_MARGIN`], so that texels alike to rounding do not tie).

use glam::{DVec2, DVec3};

use super::bindings as ids;

/// The relative difference of distances from the eye at which a texel's weight reaches zero.
pub const DISTANCE_TOLERANCE: f64 = ids::UPSAMPLE_DISTANCE_TOLERANCE as f64;
/// The least cosine between a pixel's normal and its ray the distance weight counts.
pub const MIN_FACING: f64 = ids::UPSAMPLE_MIN_FACING as f64;
/// How much more alike than the first a later texel must be to be the most alike.
pub const MISS_MARGIN: f64 = ids::UPSAMPLE_MISS_MARGIN as f64;
/// The exponent of the normals' cosine in a texel's weight.
pub const NORMAL_POWER: i32 = 8;
/// Weights summing to this or less count as no alike texel.
pub const LEAST_WEIGHT: f64 = ids::UPSAMPLE_LEAST_WEIGHT as f64;
/// The distance a texel without a surface (background) holds.
pub const NO_SURFACE: f64 = ids::UPSAMPLE_NO_SURFACE as f64;

/// A texel of the quarter-size image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfTexel {
    /// Light per unit albedo toward the surface.
    pub light: DVec3,
    /// The surface's distance from the eye ([`NO_SURFACE`] for none).
    pub distance: f64,
    pub normal: DVec3,
}

impl HalfTexel {
    /// A texel of background: no light, unlike every surface.
    pub const BACKGROUND: HalfTexel = HalfTexel {
        light: DVec3::ZERO,
        distance: NO_SURFACE,
        normal: DVec3::Z,
    };
}

/// The size of the quarter-size image of a `width` x `height` view.
pub fn half_size(width: u32, height: u32) -> (u32, u32) {
    (width.div_ceil(2), height.div_ceil(2))
}

/// The octahedral map of unit vector `n` onto [-1, 1]² (how a texel stores its normal).
pub fn octahedral(n: DVec3) -> DVec2 {
    let n = n / (n.x.abs() + n.y.abs() + n.z.abs());
    let e = DVec2::new(n.x, n.y);
    if n.z >= 0.0 {
        return e;
    }
    let sign = |v: f64| if v >= 0.0 { 1.0 } else { -1.0 };
    DVec2::new((1.0 - e.y.abs()) * sign(e.x), (1.0 - e.x.abs()) * sign(e.y))
}

/// The unit vector whose octahedral map is `e`.
pub fn from_octahedral(e: DVec2) -> DVec3 {
    let mut n = DVec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    let fold = (-n.z).max(0.0);
    n.x += if n.x >= 0.0 { -fold } else { fold };
    n.y += if n.y >= 0.0 { -fold } else { fold };
    n.normalize()
}

/// A full-resolution pixel's surface as the upsample sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSurface {
    /// The distance from the eye.
    pub distance: f64,
    pub normal: DVec3,
    /// |cos| between the normal and the ray from the eye.
    pub facing: f64,
}

impl PixelSurface {
    /// The surface at `position` with unit normal `normal`, seen from `eye`.
    pub fn seen_from(eye: DVec3, position: DVec3, normal: DVec3) -> PixelSurface {
        let distance = (eye - position).length();
        PixelSurface {
            distance,
            normal,
            facing: normal.dot(eye - position).abs() / distance,
        }
    }
}

/// The light per unit albedo the upsample gives full-resolution pixel `pixel`, showing
/// `surface`, from `texels` (row-major, `size`).
pub fn upsampled_light(
    texels: &[HalfTexel],
    size: (u32, u32),
    pixel: (u32, u32),
    surface: PixelSurface,
) -> DVec3 {
    let PixelSurface {
        distance,
        normal,
        facing,
    } = surface;
    let facing = facing.max(MIN_FACING);
    let base = (pixel.0 / 2, pixel.1 / 2);
    let f = DVec2::new(f64::from(pixel.0 % 2), f64::from(pixel.1 % 2)) * 0.5;
    let mut sum = DVec3::ZERO;
    let mut total = 0.0;
    let mut nearest = (f64::INFINITY, DVec3::ZERO);
    for (cx, cy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let x = (base.0 + cx).min(size.0 - 1);
        let y = (base.1 + cy).min(size.1 - 1);
        let texel = texels[(y * size.0 + x) as usize];
        let bilinear_x = if cx == 1 { f.x } else { 1.0 - f.x };
        let bilinear_y = if cy == 1 { f.y } else { 1.0 - f.y };
        let gap = (texel.distance - distance).abs() * facing / (DISTANCE_TOLERANCE * distance);
        let cosine = texel.normal.dot(normal).max(0.0);
        let w = bilinear_x * bilinear_y * (1.0 - gap).max(0.0) * cosine.powi(NORMAL_POWER);
        if w > 0.0 {
            sum += w * texel.light;
            total += w;
        }
        let miss = gap + 1.0 - cosine;
        if miss + MISS_MARGIN < nearest.0 {
            nearest = (miss, texel.light);
        }
    }
    if total > LEAST_WEIGHT {
        sum / total
    } else {
        nearest.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pixel's surface facing its ray.
    fn facing(distance: f64, normal: DVec3) -> PixelSurface {
        PixelSurface {
            distance,
            normal,
            facing: 1.0,
        }
    }

    fn texel(light: f64, distance: f64, normal: DVec3) -> HalfTexel {
        HalfTexel {
            light: DVec3::splat(light),
            distance,
            normal,
        }
    }

    #[test]
    fn normals_survive_the_octahedral_map() {
        let mut worst: f64 = 0.0;
        for i in 0..40 {
            for j in 0..80 {
                let theta = std::f64::consts::PI * (f64::from(i) + 0.5) / 40.0;
                let phi = std::f64::consts::TAU * f64::from(j) / 80.0;
                let n = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let e = octahedral(n);
                assert!(e.x.abs() <= 1.0 && e.y.abs() <= 1.0, "{n} -> {e}");
                worst = worst.max((from_octahedral(e) - n).length());
            }
        }
        for n in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z] {
            worst = worst.max((from_octahedral(octahedral(n)) - n).length());
        }
        assert!(worst < 1e-12, "{worst}");
    }

    #[test]
    fn a_pixel_at_even_coordinates_reads_its_own_texel() {
        let size = (3, 2);
        let texels: Vec<HalfTexel> = (0..6)
            .map(|i| texel(f64::from(i) + 1.0, 2.0, DVec3::Z))
            .collect();
        for y in 0..2u32 {
            for x in 0..3u32 {
                let light = upsampled_light(&texels, size, (2 * x, 2 * y), facing(2.0, DVec3::Z));
                assert_eq!(light, texels[(y * 3 + x) as usize].light);
            }
        }
    }

    #[test]
    fn light_that_varies_linearly_on_a_plane_is_interpolated_exactly() {
        // Texel (i, j) holds 1 + 2i + 3j: pixel (x, y) gets 1 + x + 1.5 y inside the image.
        let size = (4, 3);
        let texels: Vec<HalfTexel> = (0..12)
            .map(|k| texel(1.0 + 2.0 * f64::from(k % 4) + 3.0 * f64::from(k / 4), 5.0, DVec3::Y))
            .collect();
        for y in 0..5u32 {
            for x in 0..7u32 {
                let light = upsampled_light(&texels, size, (x, y), facing(5.0, DVec3::Y));
                let expected = 1.0 + f64::from(x) + 1.5 * f64::from(y);
                assert!((light.x - expected).abs() < 1e-12, "({x}, {y}): {light}");
            }
        }
        // Past the last texel (an even-sized view's last column, here of 8 pixels) the edge
        // texel repeats.
        let edge = upsampled_light(&texels, size, (7, 0), facing(5.0, DVec3::Y));
        assert!((edge.x - 7.0).abs() < 1e-12, "{edge}");
    }

    #[test]
    fn a_pixel_takes_only_the_texels_of_a_surface_like_its_own() {
        // A near surface (distance 1) in the left column of texels, a far one (distance 2)
        // in the right, and a wall at right angles (same distance, normal x) below.
        let size = (2, 2);
        let texels = [
            texel(10.0, 1.0, DVec3::Z),
            texel(20.0, 2.0, DVec3::Z),
            texel(30.0, 1.0, DVec3::X),
            texel(40.0, 2.0, DVec3::Z),
        ];
        // Between all four: only the near texel with the pixel's normal counts.
        let light = upsampled_light(&texels, size, (1, 1), facing(1.0, DVec3::Z));
        assert!((light.x - 10.0).abs() < 1e-12, "{light}");
        let far = upsampled_light(&texels, size, (1, 1), facing(2.0, DVec3::Z));
        assert!((far.x - 30.0).abs() < 1e-12, "the far texels' mean: {far}");
        // Within the tolerance the tent weighs a texel down, not out: between texels at 1.0
        // and 1.03 a pixel at 1.0 weighs the second by 1 - 0.03 / 0.05 = 0.4.
        let near = [texel(10.0, 1.0, DVec3::Z), texel(20.0, 1.03, DVec3::Z)];
        let close = upsampled_light(&near, (2, 1), (1, 0), facing(1.0, DVec3::Z));
        let w = 1.0 - 0.03 / DISTANCE_TOLERANCE;
        assert!((w - 0.4).abs() < 1e-6);
        let expected = (10.0 * 0.5 + 20.0 * 0.5 * w) / (0.5 + 0.5 * w);
        assert!((close.x - expected).abs() < 1e-9, "{close} against {expected}");
    }

    #[test]
    fn a_pixel_unlike_every_texel_takes_the_most_alike() {
        let size = (2, 1);
        let texels = [texel(1.0, 1.0, DVec3::Z), texel(2.0, 3.0, DVec3::Z)];
        // Distance 1.5: 10 tolerances from the first texel, 20 from the second.
        let light = upsampled_light(&texels, size, (1, 0), facing(1.5, DVec3::Z));
        assert_eq!(light.x, 1.0);
        // Background texels are never alike and never the most alike of a surface's.
        let with_background = [HalfTexel::BACKGROUND, texel(2.0, 3.0, DVec3::Z)];
        let light = upsampled_light(&with_background, size, (0, 0), facing(1.0, DVec3::Z));
        assert_eq!(light.x, 2.0);
        // Texels alike to rounding: the first, not whichever rounds closer.
        let tied = [texel(1.0, 1.0, DVec3::Z), texel(2.0, 1.0 + 1e-9, DVec3::Z)];
        let light = upsampled_light(&tied, size, (1, 0), facing(1.5, DVec3::Z));
        assert_eq!(light.x, 1.0);
    }

    #[test]
    fn a_surface_seen_at_a_grazing_angle_keeps_its_neighbours() {
        // Texels 0.1 from the pixel's distance of 1.1: unlike for a surface facing its ray
        // (1.8 tolerances), alike for one seen at a cosine of 0.2 (0.36 tolerances).
        let size = (2, 1);
        let texels = [texel(1.0, 1.0, DVec3::Z), texel(3.0, 1.2, DVec3::Z)];
        let facing_ray = upsampled_light(&texels, size, (1, 0), facing(1.1, DVec3::Z));
        assert_eq!(facing_ray.x, 1.0, "only the most alike texel (the first of two as alike)");
        let grazing = PixelSurface {
            facing: 0.2,
            ..facing(1.1, DVec3::Z)
        };
        let light = upsampled_light(&texels, size, (1, 0), grazing);
        assert!((light.x - 2.0).abs() < 1e-2, "{light}");
        let at = PixelSurface::seen_from(DVec3::ZERO, DVec3::new(0.0, 0.0, -2.0), DVec3::Z);
        assert_eq!((at.distance, at.facing), (2.0, 1.0));
    }
}
