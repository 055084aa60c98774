//! What one propagation step must move and compute per cell, for the roofline comparison in
//! `vkgi profile`. Counts are per cell and per colour channel; a multiply-add is 2 flops.
//!
//! ILPV (26 neighbours): the gather reads the light SH and the geometry of the cell and its
//! neighbours; with perfect reuse each cell's light (16 B) and geometry (16 B for an SH lobe,
//! 48 B for the projected-area model, 64 B for visibility) are read once and its result written
//! once (16 B; not where nothing reads it, as in a two-scale near field's one step a frame),
//! plus a read-modify-write of the accumulation (32 B) when accumulating. Per
//! neighbour: ⟨src|Γ⟩ 7, the blocking function (⟨B|Γ⟩ 7; the projected area: oᵀMo 12, the trace
//! 2, the product and the root 2, S·|o| 5, the min 1, V·o 5, the sum and half 2: 29; visibility:
//! picking the entry 2), the outscattered energy 1, the clamp 2, the factor 4 (mul, fma, mul, max)
//! and dst += Γ·f 8: 29 flops with an SH lobe (754 per cell), 51 with the projected area (1326),
//! 24 with visibility (624). Where the clamp compensation applies the medium before the step
//! (the default) the step only transports: no outscattered energy, and the factor a max and a
//! mul, 3 flops fewer per channel. Where a lattice runs more than one step a frame, its steps
//! apply that compensation to the result they store (the next step's source; the last computes
//! it too and stores its result raw): the medium 4, per neighbour ⟨l|Γ⟩ 7, the clamp 1, the
//! weight and the sum 2, the scale 5: 269 per channel.
//!
//! LPV (6 neighbours, 5 faces): the same bytes (light and geometry read, result written but by
//! a lone step, whose result nothing reads, the accumulation read and written every step). Per face ⟨src|eval⟩ 7, max 1, blocking 1,
//! dst += lobe·flux 8: 17; per axis 5 faces plus blocking (the mean geometry of two cells 5 with
//! an SH lobe, the blocking function, clamp 2): 99 with an SH lobe (594 per cell), 116 with the
//! projected area (696), 89 with visibility (534).
//!
//! A step that carries the three colour channels in one dispatch (`--channel-plan fused`) reads the
//! geometry once and evaluates the blocking (the function, the clamp and, for LPV's SH lobes,
//! the mean) once for all three, so per cell and channel its ideal is a third of those: ILPV
//! 26 × (20 + 9/3) = 598 flops and 80 - 2/3 × 16 bytes with an SH lobe, LPV 6 × (85 + 14/3) = 538.
//!
//! A frame's first step blocks nothing (the thesis; `--block-first-step` blocks it too): it
//! reads no geometry and evaluates no blocking, so its ideal is the transport alone (ILPV's
//! near field, whose one step a frame is that step, 442 flops and 48 bytes a cell-channel
//! fused; LPV 510).
//!
//! The lookup, per pixel: the G-buffer's position (16 B), normal and albedo (8 B each, half
//! floats) read and the HDR pixel read and written (32 B), 64 B; a lattice is small enough to
//! stay in cache, so at the ideal its cells are read once a frame, not per pixel. Arithmetic:
//! the normal's normalisation 9 and the cosine lobe 3, then per lattice the offset point 7, the
//! texture coordinate 9, the trilinear weights 22 (fractions, complements, eight corner
//! products), the blend of 8 corners × 4 coefficients × 3 channels 192, the projections on the
//! lobe 21, the clamp 3, albedo and scale 6 and the sum 3: 263. (The weights and the blend are
//! the texture unit's work where one filters in hardware; the arithmetic is still what the
//! result needs, and on a CPU device the shader does it (`--lookup-filter texels` and
//! `shared-texels`, whose shuffles move values without arithmetic). With the
//! sampler, the copy of each result lattice into the 3-D image the lookup samples, 32 B per cell
//! and channel a frame, is its own pass in the profile.)
//!
//! At half resolution, per texel of the quarter-size image (a quarter of the pixels): the
//! G-buffer's position and normal read (24 B) and the texel written (16 B), 40 B; the lookup's
//! arithmetic but albedo (3 a lattice), plus the distance to the eye 8 and the packing 20
//! (octahedral normal 12, the exponent, half floats and snorms 8). The upsample, per pixel: the G-buffer (32 B),
//! the HDR pixel read and written (32 B), and a quarter of a texel (4 B: each texel serves four
//! pixels from the cache), 68 B; the normal 9, the distance 8, per texel of four the unpacking
//! 17 (octahedral normal 12, the rest 5), bilinear weight 3, distance tent 5, the normals'
//! cosine and its eighth power 8, the product 3, the sums 4 and the most alike texel 3 (43),
//! the division 4 and albedo 3: 196.

use super::technique::Scheme;

/// Flops of the blocking of one transfer (ILPV: a neighbour; LPV: an axis) with geometry of
/// `geometry_words` words per cell: the function (⟨B|Γ⟩ 7, the projected area 29, visibility's
/// entry 2), its clamp 2 and, for LPV's SH lobes, the mean of two cells 5. None for a step that
/// reads no geometry (0 words: a frame's first, which blocks nothing).
fn blocking_flops(scheme: Scheme, geometry_words: u32) -> f64 {
    let function = match geometry_words {
        0 => return 0.0,
        1 => 7.0,
        3 => 29.0,
        _ => 2.0,
    };
    let mean = match (scheme, geometry_words) {
        (Scheme::Lpv, 1) => 5.0,
        _ => 0.0,
    };
    function + 2.0 + mean
}

/// What a step writes: its result lattice (not where nothing reads it) and its addition to the
/// accumulation.
#[derive(Clone, Copy, Debug)]
pub struct StepWrites {
    pub result: bool,
    pub accumulation: bool,
}

/// Bytes a step must move per cell and channel at the ideal (each cell read and written once),
/// when a dispatch carries `channels` colour channels (1 or 3) and reads `geometry_words` words
/// of geometry per cell (0 where it blocks nothing).
pub fn bytes_per_cell(scheme: Scheme, writes: StepWrites, geometry_words: u32, channels: u32) -> f64 {
    let geometry = 16.0 * f64::from(geometry_words) / f64::from(channels);
    let result = if writes.result { 16.0 } else { 0.0 };
    let streaming = 16.0 + geometry + result;
    let accumulation = match scheme {
        Scheme::Lpv => 32.0,
        Scheme::Ilpv if writes.accumulation => 32.0,
        Scheme::Ilpv => 0.0,
    };
    streaming + accumulation
}

/// Flops of the clamp compensation of one cell and channel.
pub const COMPENSATION_FLOPS: f64 = 4.0 + 26.0 * 10.0 + 5.0;

/// What an ILPV step does besides transport (LPV's steps only transport).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepWork {
    /// It applies absorption and scattering itself (no clamp compensation, a medium).
    AppliesMedium,
    /// It only transports (the clamp compensation has applied the medium, or there is none).
    Transports,
    /// It transports and stores its result compensated for the next step.
    TransportsAndCompensates,
}

/// Floating-point operations a step performs per cell and channel, when a dispatch carries
/// `channels` colour channels (1 or 3) and evaluates the blocking once for all of them, with
/// geometry of `geometry_words` words per cell (0: the step blocks nothing); `work`: what an
/// ILPV step does besides transport.
pub fn flops_per_cell(scheme: Scheme, work: StepWork, geometry_words: u32, channels: u32) -> f64 {
    let channels = f64::from(channels);
    let blocking = blocking_flops(scheme, geometry_words);
    match scheme {
        // Per neighbour 20 per channel (17 without the medium: the outscattered energy and
        // the factor's mul and fma); the blocking once.
        Scheme::Ilpv => {
            let per_channel = if work == StepWork::AppliesMedium {
                20.0
            } else {
                17.0
            };
            let compensation = if work == StepWork::TransportsAndCompensates {
                COMPENSATION_FLOPS
            } else {
                0.0
            };
            26.0 * (per_channel + blocking / channels) + compensation
        }
        Scheme::Lpv => 6.0 * (5.0 * 17.0 + blocking / channels),
    }
}

/// Bytes the lookup moves per pixel at the ideal.
pub const LOOKUP_BYTES_PER_PIXEL: f64 = 64.0;

/// Bytes the lookup and the upsample apart move at a pixel no surface covers: whether one does
/// (the depth, 4 B); they add nothing there. Inside direct lighting they add nothing to its.
pub const BACKGROUND_TEST_BYTES: f64 = 4.0;

/// Flops of the normal's normalisation, which a lookup inside direct lighting shares with it.
pub const NORMALISE_FLOPS: f64 = 9.0;

/// Flops of a lookup of `lattices` lattices (two for ILPV's two scales) per pixel.
pub fn lookup_flops_per_pixel(lattices: u32) -> f64 {
    NORMALISE_FLOPS + 3.0 + 263.0 * f64::from(lattices)
}

/// Bytes the half-resolution lookup moves per texel at the ideal.
pub const HALF_LOOKUP_BYTES_PER_TEXEL: f64 = 40.0;

/// Flops of the half-resolution lookup of `lattices` lattices per texel.
pub fn half_lookup_flops_per_texel(lattices: u32) -> f64 {
    lookup_flops_per_pixel(lattices) - 3.0 * f64::from(lattices) + 8.0 + 20.0
}

/// Bytes of its texels the upsample reads per pixel at the ideal (each texel serves four).
pub const UPSAMPLE_TEXEL_BYTES_PER_PIXEL: f64 = 4.0;
/// Bytes and flops of the half-resolution lookup's upsample per pixel at the ideal.
pub const UPSAMPLE_BYTES_PER_PIXEL: f64 = 64.0 + UPSAMPLE_TEXEL_BYTES_PER_PIXEL;
pub const UPSAMPLE_FLOPS_PER_PIXEL: f64 = 9.0 + 8.0 + 4.0 * 43.0 + 4.0 + 3.0;

#[cfg(test)]
mod tests {
    use super::*;

    const APPLIES: StepWork = StepWork::AppliesMedium;
    const TRANSPORTS: StepWork = StepWork::Transports;

    #[test]
    fn counts_follow_the_derivation() {
        let compensates = StepWork::TransportsAndCompensates;
        assert_eq!(flops_per_cell(Scheme::Ilpv, compensates, 1, 3), 520.0 + 269.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, APPLIES, 1, 1), 754.0);
        assert_eq!(flops_per_cell(Scheme::Lpv, TRANSPORTS, 1, 1), 594.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, APPLIES, 3, 1), 1326.0);
        assert_eq!(flops_per_cell(Scheme::Lpv, TRANSPORTS, 3, 1), 696.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, APPLIES, 4, 1), 624.0);
        assert_eq!(flops_per_cell(Scheme::Lpv, TRANSPORTS, 4, 1), 534.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, APPLIES, 1, 3), 598.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, TRANSPORTS, 1, 3), 520.0);
        assert_eq!(flops_per_cell(Scheme::Lpv, TRANSPORTS, 1, 3), 538.0);
        // A frame's first step, which blocks nothing: transport alone.
        assert_eq!(flops_per_cell(Scheme::Ilpv, TRANSPORTS, 0, 3), 442.0);
        assert_eq!(flops_per_cell(Scheme::Ilpv, TRANSPORTS, 0, 1), 442.0);
        assert_eq!(flops_per_cell(Scheme::Lpv, TRANSPORTS, 0, 3), 510.0);
        let writes = |result, accumulation| StepWrites {
            result,
            accumulation,
        };
        assert_eq!(bytes_per_cell(Scheme::Ilpv, writes(true, false), 1, 1), 48.0);
        assert_eq!(bytes_per_cell(Scheme::Lpv, writes(true, true), 1, 1), 80.0);
        assert_eq!(bytes_per_cell(Scheme::Ilpv, writes(true, false), 3, 1), 80.0);
        assert_eq!(bytes_per_cell(Scheme::Ilpv, writes(true, false), 4, 1), 96.0);
        assert_eq!(bytes_per_cell(Scheme::Ilpv, writes(true, false), 3, 3), 48.0);
        // A two-scale near field's step writes the accumulation alone.
        let near_field = bytes_per_cell(Scheme::Ilpv, writes(false, true), 1, 3);
        assert!((near_field - 160.0 / 3.0).abs() < 1e-12, "{near_field}");
        // ... which, blocking nothing (the first of a frame), reads no geometry.
        assert_eq!(bytes_per_cell(Scheme::Ilpv, writes(false, true), 0, 3), 48.0);
        assert_eq!(lookup_flops_per_pixel(1), 275.0);
        assert_eq!(lookup_flops_per_pixel(2), 538.0);
        assert_eq!(half_lookup_flops_per_texel(1), 300.0);
        assert_eq!(half_lookup_flops_per_texel(2), 560.0);
        assert_eq!(UPSAMPLE_FLOPS_PER_PIXEL, 196.0);
    }
}
