//! What the apply pass (apply.comp) must move and compute per pixel at the ideal, for the bound
//! `vkgi profile` states it against (as src/render/cost.rs does for the frame's passes). A
//! multiply-add is 2 flops; a comparison, clamp bound, floor, min or max counts 1.
//!
//! * **Bytes** at a covered pixel: the G-buffer's position (16 B), normal and albedo (8 B
//!   each), the HDR pixel read and written (16 B each): 64 B. At a pixel no surface covers,
//!   whether one does (the depth, 4 B). The address volume and the corner caches serve many
//!   pixels (at the ideal, read once a frame), as lattice cells do for the LPV lookup.
//! * **Flops** at a covered pixel, interpolating one cascade: its decision box's 6 comparisons,
//!   and with a transition the distance to the box's faces (6 differences, 5 minima) and the
//!   blend (a product, a difference, a clamp's 2): 15; the cell and the position in it (the
//!   offset and scale 6, floor 3, clamp to the grid 6, fraction 3): 18; the normal normalised
//!   (dot 5, reciprocal square root 1, scale 3): 9; the SH basis at the normal with the cosine
//!   lobe's factors folded into its constants (L1 3; L2 17: the second band's five 14 more);
//!   the trilinear weights (1 - f 3, the products 12): 15; per corner its irradiance (3
//!   channels times C multiply-adds), the clamp to zero 3 and the weighted sum 6; with
//!   `--corners front` whether each corner lies in front of the surface (the base corner's
//!   offset along the normal 11, per corner the offset's sum 2 and a comparison 1): 35; albedo
//!   times the irradiance over pi (6) added to the pixel (3): 9.
//!
//! Pixels within `--transition` cells of a decision box's face blend in the next cascade's
//! interpolation too: their share depends on the view, so the bound leaves it out and is a floor
//! there. With indirect specular the glossy pixels sum their corner caches' hemisphere maps
//! under their lobes, work that depends on which pixels are glossy: no bound is stated then.

use super::{Bands, VolumeSettings};
use crate::gi::PixelPass;

/// The pass's name in the profile.
pub const APPLY: &str = "rv apply";

/// What the pass moves at a covered pixel and at a background pixel.
const BYTES_PER_PIXEL: f64 = 16.0 + 8.0 + 8.0 + 16.0 + 16.0;
const BACKGROUND_BYTES: f64 = 4.0;

/// The apply pass's bound, or None where indirect specular is on.
pub fn apply_pass(settings: &VolumeSettings) -> Option<PixelPass> {
    (settings.specular == 0).then(|| PixelPass {
        pass: APPLY,
        bytes_per_pixel: BYTES_PER_PIXEL,
        flops_per_pixel: apply_flops(settings),
        with_direct_lighting: false,
        background_bytes: Some(BACKGROUND_BYTES),
    })
}

/// The flops of one covered pixel's diffuse apply (module comment).
fn apply_flops(settings: &VolumeSettings) -> f64 {
    let coefficients = f64::from(settings.bands.coefficients());
    let cascade = 6.0 + if settings.transition > 0.0 { 15.0 } else { 0.0 };
    let basis = match settings.bands {
        Bands::L1 => 3.0,
        Bands::L2 => 17.0,
    };
    let front = if settings.front_corners { 35.0 } else { 0.0 };
    let per_corner = 3.0 * coefficients * 2.0 + 3.0 + 6.0;
    cascade + 18.0 + 9.0 + basis + 15.0 + front + 8.0 * per_corner + 9.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gi::radiance_volumes::voxelizer::VoxelizerChoice;

    fn settings(bands: Bands, transition: f32, front_corners: bool, specular: u32) -> VolumeSettings {
        VolumeSettings {
            cascades: 3,
            resolution: 32,
            reach: 1.0,
            transition,
            capacity: 16384,
            bands,
            rsm: 256,
            val_budget: 4096,
            front_corners,
            shadows: true,
            voxels: 128,
            voxelizer: VoxelizerChoice::Auto,
            shadow_lod: 2,
            voxel_fade: 3,
            specular,
        }
    }

    #[test]
    fn the_apply_bound_counts_what_each_setting_adds() {
        let defaults = apply_pass(&settings(Bands::L1, 2.0, false, 0)).unwrap();
        // 21 + 18 + 9 + 3 + 15 + 8 x (24 + 9) + 9.
        assert_eq!(defaults.flops_per_pixel, 339.0);
        assert_eq!(defaults.bytes_per_pixel, 64.0);
        assert_eq!(defaults.ideal(10, 4), (4.0 * 64.0 + 6.0 * 4.0, 4.0 * 339.0));
        // L2: 14 more for the basis, 8 x 3 x 5 multiply-adds more over the corners.
        let l2 = apply_pass(&settings(Bands::L2, 2.0, false, 0)).unwrap();
        assert_eq!(l2.flops_per_pixel, 339.0 + 14.0 + 240.0);
        let hard_seam = apply_pass(&settings(Bands::L1, 0.0, false, 0)).unwrap();
        assert_eq!(hard_seam.flops_per_pixel, 339.0 - 15.0);
        let front = apply_pass(&settings(Bands::L1, 2.0, true, 0)).unwrap();
        assert_eq!(front.flops_per_pixel, 339.0 + 35.0);
        assert!(apply_pass(&settings(Bands::L1, 2.0, false, 8)).is_none());
    }
}
