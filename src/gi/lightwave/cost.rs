//! What the gather pass (composite.glsl with gather.comp or gather_vertex.comp) must move and
//! compute per pixel at the ideal, for the bound `vkgi profile` states it against (as
//! src/render/cost.rs does for the frame's passes). A multiply-add is 2 flops; a comparison,
//! clamp bound, select, square root or division counts 1.
//!
//! * **Bytes** at a covered pixel: the G-buffer's position (16 B), normal and albedo (8 B each),
//!   the HDR pixel read and written (16 B each): 64 B; per vertex the pixel's triangle too (4
//!   B). At a pixel no surface covers, whether one does (the depth, 4 B). The VPLs, the corners'
//!   gathered values and the shadow maps' texels serve many pixels (at the ideal, read once a
//!   frame).
//! * **Flops** at a covered pixel: the normal normalised 9 (dot 5, reciprocal square root 1,
//!   scale 3), albedo over pi 3, the light added to the pixel 3 (the albedo's product 3 more
//!   where the gather's light is added). Where the composite adds the gathered light (eq4.9,
//!   shipped), per light: the gather, at every pixel the mean over the rig's VPLs (per VPL the
//!   offset 3, its squared length 5, the zero test 1, the reciprocal square root 1, the
//!   direction 3, the two cosines 10, the clamp 2, the lobe's multiply-add and clamp 4, the
//!   weighted sum 3: 32; the mean 1), per vertex the corners' values for the pixel's side (3
//!   selects, a dot product 5: 8) after, once a pixel, the barycentric weights (the edges and
//!   offset 9, five dot products 25, the determinant 3, its test 3, the two weights 8, the
//!   third 2) and the interpolated normal and side (15 and 6): 71; the visibility (below); the
//!   light's irradiance added (the product of gain, gather and visibility 2, the intensity's
//!   multiply-add 6), shipped's 0.2/0.8 split 2 more. Where the composite adds the direct
//!   light (shipped, fake), per light direct lighting's 146 (src/render/cost.rs) and the
//!   unshadowed sum 6, and once a pixel the mix of the two 10 and its product with the albedo
//!   and sum 6.
//! * **Visibility** per light: accurate, per map the pixel's clip position (the distance to the
//!   VPL 9, the offset along the normal 8, the 4x4 projection 24: 41), the tap (the w test 1,
//!   the divide 4, the map coordinates 4, the bounds tests 5, the texel coordinates, floor and
//!   fractions 8, 4 comparisons, the bilinear weights 9: 35) and the sum 1, the mean 1;
//!   integrated, the 5 maps' clip positions (41 each), per pair of maps and step the clip
//!   position interpolated 12, a tap 35 and the sum 1, the midpoint's second tap and mean 38
//!   more where the steps are even, and the mean 2. Every tap is counted whole, as direct
//!   lighting counts every light's shadow lookup whole at every covered pixel.
//!
//! The direct-only composite adds nothing: its pass states no bound.

use super::{LightWaveSettings, ShadowMode};
use crate::gi::PixelPass;
use crate::render::cost::FLOPS_PER_LIGHT;

/// The pass's name in the profile.
pub const GATHER: &str = "lightwave gather";

/// What the pass moves at a covered pixel (per pixel; per vertex 4 B more) and at a background
/// pixel.
const BYTES_PER_PIXEL: f64 = 16.0 + 8.0 + 8.0 + 16.0 + 16.0;
const TRIANGLE_BYTES: f64 = 4.0;
const BACKGROUND_BYTES: f64 = 4.0;

/// Flops of the pieces the module comment counts.
const PER_VPL: f64 = 32.0;
const PER_VERTEX_PIXEL: f64 = 71.0;
const PER_VERTEX_LIGHT: f64 = 8.0;
const CLIP: f64 = 41.0;
const TAP: f64 = 35.0;
const DIRECT_PER_LIGHT: f64 = FLOPS_PER_LIGHT + 6.0;

/// The gather pass's bound with `lights` lights and `maps_per_light` VPL shadow maps per light,
/// or None for the direct-only composite.
pub fn gather_pass(settings: &LightWaveSettings, lights: u32, maps_per_light: u32) -> Option<PixelPass> {
    let gathers = settings.uses_indirect();
    let direct = matches!(settings.composite, "shipped" | "fake");
    if !gathers && !direct {
        return None;
    }
    let lights = f64::from(lights);
    let mut per_pixel = 9.0 + 3.0 + 3.0;
    let mut per_light = 0.0;
    if gathers {
        per_pixel += 3.0;
        per_light += 8.0 + visibility_flops(settings, maps_per_light);
        if settings.composite == "shipped" && settings.shadows == ShadowMode::Accurate {
            per_light += 2.0;
        }
        if settings.per_vertex {
            per_pixel += PER_VERTEX_PIXEL;
            per_light += PER_VERTEX_LIGHT;
        } else {
            per_light += PER_VPL * f64::from(settings.rig.count()) + 1.0;
        }
    }
    if direct {
        per_pixel += 10.0 + 6.0;
        per_light += DIRECT_PER_LIGHT;
    }
    Some(PixelPass {
        pass: GATHER,
        bytes_per_pixel: BYTES_PER_PIXEL + if settings.per_vertex { TRIANGLE_BYTES } else { 0.0 },
        flops_per_pixel: per_pixel + per_light * lights,
        with_direct_lighting: false,
        background_bytes: Some(BACKGROUND_BYTES),
    })
}

/// The flops of one light's indirect visibility at a pixel.
fn visibility_flops(settings: &LightWaveSettings, maps_per_light: u32) -> f64 {
    match settings.shadows {
        ShadowMode::None => 0.0,
        ShadowMode::Accurate => f64::from(maps_per_light) * (CLIP + TAP + 1.0) + 1.0,
        ShadowMode::Integrated => {
            let taps = f64::from(settings.steps + 1);
            let midpoint = if settings.steps.is_multiple_of(2) { TAP + 3.0 } else { 0.0 };
            5.0 * CLIP + 10.0 * (taps * (12.0 + TAP + 1.0) + midpoint) + 2.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gi::lightwave::rig::Rig;

    fn settings(per_vertex: bool, shadows: ShadowMode, composite: &'static str) -> LightWaveSettings {
        LightWaveSettings {
            rig: Rig::new(30, 2, 1.0).unwrap(),
            per_vertex,
            shadows,
            shadow_set: Vec::new(),
            steps: 4,
            shadow_ratio: 3.0,
            composite,
            fake: 1.3,
            gain: Some(1.0),
            fit_spp: 16,
        }
    }

    #[test]
    fn the_gather_bound_counts_what_each_setting_adds() {
        // The defaults' shape: per vertex, 20 accurate maps, eq4.9, one light.
        let vertex = gather_pass(&settings(true, ShadowMode::Accurate, "eq4.9"), 1, 20).unwrap();
        assert_eq!(vertex.bytes_per_pixel, 68.0);
        assert_eq!(vertex.flops_per_pixel, 18.0 + 71.0 + 8.0 + 8.0 + 20.0 * 77.0 + 1.0);
        assert_eq!(vertex.ideal(10, 4), (4.0 * 68.0 + 6.0 * 4.0, 4.0 * vertex.flops_per_pixel));
        // Per pixel, every VPL of the rig instead of the corners' values; two lights twice
        // the per-light part.
        let rig = settings(false, ShadowMode::None, "eq4.9").rig.count();
        let pixel = gather_pass(&settings(false, ShadowMode::None, "eq4.9"), 2, 0).unwrap();
        assert_eq!(pixel.bytes_per_pixel, 64.0);
        assert_eq!(pixel.flops_per_pixel, 18.0 + 2.0 * (8.0 + 32.0 * f64::from(rig) + 1.0));
        // Integrated with 4 steps: 5 clip positions, 10 pairs of 5 taps and a midpoint.
        let integrated = gather_pass(&settings(true, ShadowMode::Integrated, "eq4.9"), 1, 5).unwrap();
        let visibility = 5.0 * 41.0 + 10.0 * (5.0 * 48.0 + 38.0) + 2.0;
        assert_eq!(integrated.flops_per_pixel, 18.0 + 71.0 + 8.0 + 8.0 + visibility);
        // Shipped adds the split and the direct light; fake only the direct light.
        let shipped = gather_pass(&settings(true, ShadowMode::Accurate, "shipped"), 1, 20).unwrap();
        assert_eq!(shipped.flops_per_pixel, vertex.flops_per_pixel + 2.0 + 16.0 + 152.0);
        let fake = gather_pass(&settings(false, ShadowMode::None, "fake"), 1, 0).unwrap();
        assert_eq!(fake.flops_per_pixel, 15.0 + 16.0 + 152.0);
        assert!(gather_pass(&settings(false, ShadowMode::None, "direct-only"), 1, 0).is_none());
    }
}
