//! Two-band spherical harmonics in the convention of seed 000 (Kaplanyan/Engel/Dachsbacher):
//! coefficients (Y00, Y1-1, Y10, Y11) with the Condon–Shortley sign folded in, so a function's
//! SH vector evaluates as `c · basis(ω)` and the clamped-cosine lobe around n is
//! `(c0, -c1 n_y, c1 n_z, -c1 n_x)`. The same functions exist in shaders-glsl/gi/shared/sh.glsl.

use glam::{DVec3, DVec4};

/// √π / 2: the DC coefficient of the clamped-cosine lobe.
pub const C0: f64 = 0.886_226_925_452_758;
/// √(π/3): the linear coefficients' scale of the clamped-cosine lobe.
pub const C1: f64 = 1.023_326_707_946_488_5;
/// 2√π: ⟨f|1⟩ = 2√π f.x, the integral of the function over the sphere.
pub const SQRT_PI_2: f64 = 3.544_907_701_811_032;

/// Y00 = 1/(2√π) and Y1m = √(3/(4π)).
const Y0: f64 = 0.282_094_791_773_878_14;
const Y1: f64 = 0.488_602_511_902_919_9;

/// The SH projection of the clamped cosine lobe max(0, n·ω) around unit `n`.
pub fn cosine_lobe(n: DVec3) -> DVec4 {
    DVec4::new(C0, -C1 * n.y, C1 * n.z, -C1 * n.x)
}

/// The basis functions evaluated at unit direction `w`: a function's value there is `c · basis`.
pub fn basis(w: DVec3) -> DVec4 {
    DVec4::new(Y0, -Y1 * w.y, Y1 * w.z, -Y1 * w.x)
}

/// Integral of the function over the sphere (its energy).
pub fn energy(c: DVec4) -> f64 {
    SQRT_PI_2 * c.x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identities_of_the_cosine_lobe() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let lobe = cosine_lobe(n);
        // ⟨SH_cos(ω)|SH_cos(ω)⟩ = π/4 + π/3 and its energy is π.
        let pi = std::f64::consts::PI;
        assert!((lobe.dot(lobe) - (pi / 4.0 + pi / 3.0)).abs() < 1e-12);
        assert!((energy(lobe) - pi).abs() < 1e-12);
        // Evaluated along n, the 2-band lobe gives c0 Y0 + c1 Y1 = 1/4 + 1/2.
        assert!((lobe.dot(basis(n)) - 0.75).abs() < 1e-12);
        // ⟨SH_cos(a)|SH_cos(b)⟩ = π/4 + (π/3) a·b.
        let m = DVec3::new(-0.2, 0.9, 0.1).normalize();
        assert!((lobe.dot(cosine_lobe(m)) - (pi / 4.0 + pi / 3.0 * n.dot(m))).abs() < 1e-12);
    }

    #[test]
    fn projection_of_the_clamped_cosine_matches_numerical_integration() {
        let n = DVec3::new(0.0, 0.6, 0.8);
        let steps = 400;
        let mut c = DVec4::ZERO;
        for i in 0..steps {
            for j in 0..2 * steps {
                let theta = (i as f64 + 0.5) / steps as f64 * std::f64::consts::PI;
                let phi = (j as f64 + 0.5) / (2 * steps) as f64 * 2.0 * std::f64::consts::PI;
                let w = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let d_omega = theta.sin() * (std::f64::consts::PI / steps as f64).powi(2);
                c += basis(w) * n.dot(w).max(0.0) * d_omega;
            }
        }
        assert!(
            (c - cosine_lobe(n)).abs().max_element() < 1e-4,
            "{c} vs {}",
            cosine_lobe(n)
        );
    }
}
