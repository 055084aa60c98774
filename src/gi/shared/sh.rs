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

/// √(15/(4π)), √(5/(16π)) and √(15/(16π)): the scales of band 2's xy/yz/xz, 3z²-1 and x²-y²
/// functions.
const Y2_CROSS: f64 = 1.092_548_430_592_079_2;
const Y2_ZONAL: f64 = 0.315_391_565_252_520_05;
const Y2_SQUARES: f64 = 0.546_274_215_296_039_6;

/// Coefficients of the three-band (L2) basis.
pub const L2_COEFFICIENTS: usize = 9;

/// The three-band basis at unit direction `w`, in the same convention: the first four are
/// [`basis`], then (Y2-2, Y2-1, Y20, Y21, Y22) with the sign of odd m folded in as in band 1.
pub fn basis_l2(w: DVec3) -> [f64; L2_COEFFICIENTS] {
    [
        Y0,
        -Y1 * w.y,
        Y1 * w.z,
        -Y1 * w.x,
        Y2_CROSS * w.x * w.y,
        -Y2_CROSS * w.y * w.z,
        Y2_ZONAL * (3.0 * w.z * w.z - 1.0),
        -Y2_CROSS * w.x * w.z,
        Y2_SQUARES * (w.x * w.x - w.y * w.y),
    ]
}

/// The band of coefficient `i` (0, 1 or 2).
pub fn band_of(i: usize) -> usize {
    match i {
        0 => 0,
        1..=3 => 1,
        _ => 2,
    }
}

/// Â_l, the clamped cosine's convolution factor per band (Ramamoorthi & Hanrahan 2001): the
/// irradiance at normal n of radiance with coefficients c is Σ Â_l c_lm Y_lm(n).
pub const COSINE_CONVOLUTION: [f64; 3] = [
    std::f64::consts::PI,
    2.0 * std::f64::consts::PI / 3.0,
    std::f64::consts::PI / 4.0,
];

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

    /// Midpoint quadrature over the sphere: (direction, solid angle) pairs.
    fn sphere_quadrature(steps: usize) -> Vec<(DVec3, f64)> {
        let pi = std::f64::consts::PI;
        let mut points = Vec::with_capacity(2 * steps * steps);
        for i in 0..steps {
            for j in 0..2 * steps {
                let theta = (i as f64 + 0.5) / steps as f64 * pi;
                let phi = (j as f64 + 0.5) / (2 * steps) as f64 * 2.0 * pi;
                let w = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                points.push((w, theta.sin() * (pi / steps as f64).powi(2)));
            }
        }
        points
    }

    #[test]
    fn the_l2_basis_is_orthonormal_and_extends_the_l1_basis() {
        let quadrature = sphere_quadrature(300);
        for a in 0..L2_COEFFICIENTS {
            for b in 0..L2_COEFFICIENTS {
                let inner: f64 = quadrature
                    .iter()
                    .map(|&(w, d)| basis_l2(w)[a] * basis_l2(w)[b] * d)
                    .sum();
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((inner - expected).abs() < 1e-4, "<Y{a}|Y{b}> = {inner}");
            }
        }
        let w = DVec3::new(0.48, -0.6, 0.64);
        let l1 = basis(w);
        assert_eq!(basis_l2(w)[..4], [l1.x, l1.y, l1.z, l1.w]);
    }

    #[test]
    fn one_direction_projected_and_convolved_is_the_truncated_legendre_series() {
        // Addition theorem: Σ_m Y_lm(a) Y_lm(b) = (2l+1)/(4π) P_l(a·b), so the irradiance of
        // a unit delta of radiance from `a` at normal `b` is Σ_l Â_l (2l+1)/(4π) P_l(a·b).
        let pi = std::f64::consts::PI;
        let a = DVec3::new(0.2, -0.7, 0.4).normalize();
        for b in [
            DVec3::new(0.9, 0.1, -0.3).normalize(),
            a,
            -a,
            DVec3::new(0.0, 0.0, 1.0),
        ] {
            let t = a.dot(b);
            let legendre = [1.0, t, 0.5 * (3.0 * t * t - 1.0)];
            let (ya, yb) = (basis_l2(a), basis_l2(b));
            for bands in [2, 3] {
                let n = bands * bands;
                let sh: f64 = (0..n)
                    .map(|i| COSINE_CONVOLUTION[band_of(i)] * ya[i] * yb[i])
                    .sum();
                let series: f64 = (0..bands)
                    .map(|l| COSINE_CONVOLUTION[l] * (2 * l + 1) as f64 / (4.0 * pi) * legendre[l])
                    .sum();
                assert!((sh - series).abs() < 1e-12, "{bands} bands at a·b = {t}");
            }
        }
    }

    #[test]
    fn irradiance_of_quadratic_radiance_is_exact_in_l2_and_linear_radiance_in_l1() {
        // Radiance of degree ≤ l in ω lies in bands ≤ l, so its SH irradiance equals the
        // brute-force cosine-weighted integral (up to quadrature error).
        let quadrature = sphere_quadrature(200);
        let linear = |w: DVec3| 1.0 + 0.5 * w.x - 0.3 * w.y + 0.2 * w.z;
        let quadratic = |w: DVec3| linear(w) + 0.4 * w.x * w.y - 0.3 * w.z * w.z + 0.2 * w.y * w.y;
        for (bands, radiance) in [
            (2, &linear as &dyn Fn(DVec3) -> f64),
            (3, &quadratic as &dyn Fn(DVec3) -> f64),
        ] {
            let n = bands * bands;
            let mut c = [0.0; L2_COEFFICIENTS];
            for &(w, d) in &quadrature {
                for (ci, yi) in c.iter_mut().zip(basis_l2(w)).take(n) {
                    *ci += radiance(w) * yi * d;
                }
            }
            for normal in [
                DVec3::Z,
                DVec3::new(0.6, -0.8, 0.0),
                DVec3::new(-0.36, 0.48, -0.8),
            ] {
                let brute: f64 = quadrature
                    .iter()
                    .map(|&(w, d)| radiance(w) * normal.dot(w).max(0.0) * d)
                    .sum();
                let y = basis_l2(normal);
                let sh: f64 = (0..n)
                    .map(|i| COSINE_CONVOLUTION[band_of(i)] * c[i] * y[i])
                    .sum();
                assert!(
                    (sh - brute).abs() < 2e-3 * brute,
                    "{bands} bands: {sh} vs {brute}"
                );
            }
        }
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
