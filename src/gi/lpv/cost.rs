//! What one propagation step must move and compute per cell, for the roofline comparison in
//! `vkgi profile`. Counts are per cell and per colour channel; a multiply-add is 2 flops.
//!
//! ILPV (26 neighbours): the gather reads the light and geometry SH of the cell and its
//! neighbours; with perfect reuse each cell's 2 vec4 are read once (32 B) and its result written
//! once (16 B), plus a read-modify-write of the accumulation (32 B) when accumulating. Per
//! neighbour: ⟨src|Γ⟩ 7, ⟨B|Γ⟩ 7, the outscattered energy 1, blocking 2, the factor 4
//! (mul, fma, mul, max) and dst += Γ·f 8: 29 flops, 754 per cell.
//!
//! LPV (6 neighbours, 5 faces): the same bytes (light and geometry read, result written, the
//! accumulation read and written every step). Per face ⟨src|eval⟩ 7, max 1, blocking 1,
//! dst += lobe·flux 8: 17; per axis 5 faces plus blocking (mean geometry 5, ⟨B|Γ⟩ 7,
//! clamp 2): 99, 594 per cell.

use super::technique::Scheme;

/// Bytes a step must move per cell at the ideal (each cell read and written once).
pub fn bytes_per_cell(scheme: Scheme, accumulate: bool) -> f64 {
    let streaming = 32.0 + 16.0;
    let accumulation = match scheme {
        Scheme::Lpv => 32.0,
        Scheme::Ilpv if accumulate => 32.0,
        Scheme::Ilpv => 0.0,
    };
    streaming + accumulation
}

/// Floating-point operations a step performs per cell.
pub fn flops_per_cell(scheme: Scheme) -> f64 {
    match scheme {
        Scheme::Ilpv => 26.0 * 29.0,
        Scheme::Lpv => 6.0 * (5.0 * 17.0 + 14.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_follow_the_derivation() {
        assert_eq!(flops_per_cell(Scheme::Ilpv), 754.0);
        assert_eq!(flops_per_cell(Scheme::Lpv), 594.0);
        assert_eq!(bytes_per_cell(Scheme::Ilpv, false), 48.0);
        assert_eq!(bytes_per_cell(Scheme::Lpv, true), 80.0);
    }
}
