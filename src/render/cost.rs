//! What the frame's own per-pixel passes must move and compute per pixel at the ideal, for the
//! bound `vkgi profile` measures them against (as src/gi/lpv/cost.rs does for propagation). A
//! multiply-add is 2 flops; a square root, division or comparison counts 1.
//!
//! * **G-buffer**: position (16 B), normal, albedo, and where a material has them emission and
//!   the glossy lobe (8 B each, half floats) and depth (4 B) written, depth read by the test (4
//!   B): 56 B per covered pixel, 40 B without emission and glossy lobes, each pixel drawn once
//!   (overdraw is the scene's, not the pass's). Arithmetic: the varyings' interpolation 32,
//!   facing 8, the shading normal 20: 60.
//! * **Direct lighting**: the G-buffer's position, normal and albedo read (32 B), its emission
//!   and glossy lobe where a material has them (8 B each), and the HDR pixel written (16 B): 48
//!   to 64 B (a shadow texel serves many neighbouring pixels: at the ideal each is read once a
//!   frame). Arithmetic: the normal and the direction to the eye 21, the sum 6 (9 with
//!   emission), and per light the incidence 17, the cosine 5, the shadow view 3, the 3x3
//!   bilinear PCF 114 (the offset point 5, the 4x4 projection 28, the divide 4, texel
//!   coordinates and fractions 12, weights 2, 16 comparisons and 16 weighted sums 64, the
//!   scale 1) and the accumulation 7: 146, with a glossy lobe 40 more (two cosines 10, the half
//!   vector 12, D 6, the two G1 8, the product 4).
//! * **Direct lighting at a background pixel**: whether a surface covers it (the depth, 4 B)
//!   and the HDR pixel written (16 B): 20 B and no arithmetic (the fragment form shades only
//!   covered pixels). The G-buffer's background pixels are its clear values, as many bytes as
//!   a covered pixel's, and the tone map reads and writes every pixel: both cost the same at
//!   every pixel.
//! * **Tone map**: the HDR pixel read (16 B) and the 8-bit pixel written (4 B): 20 B.
//!   Arithmetic: exposure 3, Reinhard 6, the sRGB curve 15: 24.

use super::passes::{DIRECT_LIGHTING, GBUFFER, MaterialTerms, TONE_MAP};
use crate::gi::PixelPass;

/// Direct lighting's flops per light at a covered pixel without a glossy lobe: incidence,
/// cosine, shadow view, the 3x3 bilinear PCF and the accumulation (module comment).
pub const FLOPS_PER_LIGHT: f64 = 146.0;

/// What direct lighting moves at a pixel no surface covers: the depth read, the HDR pixel
/// written.
pub const BACKGROUND_BYTES: f64 = 4.0 + 16.0;

/// The frame's per-pixel passes with `lights` rasterised lights and materials with `terms`.
pub fn pixel_passes(lights: u32, terms: MaterialTerms) -> Vec<PixelPass> {
    let optional = |present: bool, value: f64| if present { value } else { 0.0 };
    vec![
        PixelPass {
            pass: GBUFFER,
            bytes_per_pixel: 40.0 + optional(terms.emissive || terms.glossy, 16.0),
            flops_per_pixel: 60.0,
            with_direct_lighting: false,
            background_bytes: None,
        },
        PixelPass {
            pass: DIRECT_LIGHTING,
            bytes_per_pixel: 48.0 + optional(terms.emissive, 8.0) + optional(terms.glossy, 8.0),
            flops_per_pixel: 27.0
                + optional(terms.emissive, 3.0)
                + (FLOPS_PER_LIGHT + optional(terms.glossy, 40.0)) * f64::from(lights),
            with_direct_lighting: false,
            background_bytes: Some(BACKGROUND_BYTES),
        },
        PixelPass {
            pass: TONE_MAP,
            bytes_per_pixel: 20.0,
            flops_per_pixel: 24.0,
            with_direct_lighting: false,
            background_bytes: None,
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn background_pixels_are_held_to_their_bytes_and_no_flops() {
        let plain = MaterialTerms {
            emissive: false,
            glossy: false,
        };
        let passes = pixel_passes(1, plain);
        let direct = passes.iter().find(|p| p.pass == DIRECT_LIGHTING).unwrap();
        // 100 pixels, 70 of them covered: 70 at the full cost, 30 at the background's 20 B.
        let (bytes, flops) = direct.ideal(100, 70);
        assert_eq!(bytes, 70.0 * 48.0 + 30.0 * 20.0);
        assert_eq!(flops, 70.0 * (27.0 + 146.0));
        // Every pixel covered: the full cost everywhere; more covered than pixels counts all.
        assert_eq!(direct.ideal(100, 100), (4800.0, 17300.0));
        assert_eq!(direct.ideal(100, 500), (4800.0, 17300.0));
        // The G-buffer's background pixels are its clears: every pixel the same.
        let gbuffer = passes.iter().find(|p| p.pass == GBUFFER).unwrap();
        assert_eq!(gbuffer.ideal(100, 0), (4000.0, 6000.0));
    }
}
