//! The hemisphere camera's constant per-texel tables (spec 003 §6, §10), in f64: what each texel
//! of the R×R sampling plane contributes to a record's irradiance E, rotation gradient and
//! translation gradient, for the three ways of treating the directions the plane misses.
//!
//! The camera sits on the record looking along its normal (local z); texel (i, j) covers the
//! plane square x ∈ [x_i, x_{i+1}], y ∈ [y_j, y_{j+1}] at z = 1, with x_k = t(2k/R − 1) and
//! t = tan(fov/2) = 2 (the chapter's 126.87° aperture). Column i grows along the local x axis
//! (the basis's tangent), row j along y (its bitangent).
//!
//! - weight W: ∫ cosθ dω over the texel's directions, so E = Σ W·L;
//! - rotation Wr: ∫ (ẑ × ω) dω (its x, y; z is 0), so ∇_r E = Σ Wr·L;
//! - edges G: for the edge to the next texel along x (`right`) and along y (`down`),
//!   the tangent-plane part of ∫_edge cosθ m dℓ (m: the unit normal to the edge on the sphere,
//!   pointing into the next texel), so ∇_t E = Σ_edges (L_next − L)·G / min(d, d_next).
//!
//! With border stretching the border texels also own the directions between the plane's edge
//! and the horizon along their azimuths, so W sums to π and the edges between neighbouring
//! border texels run on to the horizon.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

/// tan of half the hemisphere camera's aperture.
pub const HALF_WIDTH: f64 = 2.0;

/// What the hemisphere does with the directions outside the plane (`--hemisphere`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coverage {
    /// The chapter's method: border texels stretched to the horizon.
    Stretch,
    /// The plane alone (the directions it misses count as black).
    Plane,
    /// [LC04]: the plane, divided by the fraction of the cosine-weighted hemisphere it covers.
    Lc04,
}

impl Coverage {
    pub const NAMES: &'static [&'static str] = &["stretch", "plane", "lc04"];

    pub fn parse(name: &str) -> Option<Coverage> {
        match name {
            "stretch" => Some(Coverage::Stretch),
            "plane" => Some(Coverage::Plane),
            "lc04" => Some(Coverage::Lc04),
            _ => None,
        }
    }
}

/// Per-texel tables of an R×R plane, row-major (index j·R + i).
#[derive(Clone, Debug)]
pub struct Tables {
    pub resolution: usize,
    pub weight: Vec<f64>,
    pub rotation: Vec<[f64; 2]>,
    /// Edge to texel (i+1, j); zero in the last column.
    pub right: Vec<[f64; 2]>,
    /// Edge to texel (i, j+1); zero in the last row.
    pub down: Vec<[f64; 2]>,
}

/// Plane coordinate of pixel edge k (0..=R).
pub fn edge(k: usize, resolution: usize) -> f64 {
    HALF_WIDTH * (2.0 * k as f64 / resolution as f64 - 1.0)
}

/// Unit direction (record frame) through the centre of texel (i, j).
pub fn texel_direction(i: usize, j: usize, resolution: usize) -> DVec3 {
    let centre = |k: usize| HALF_WIDTH * (2.0 * (k as f64 + 0.5) / resolution as f64 - 1.0);
    DVec3::new(centre(i), centre(j), 1.0).normalize()
}

/// ∫∫ dx dy / (1 + x² + y²)² over [0, x] × [0, y] (odd in x and in y).
fn cosine_integral(x: f64, y: f64) -> f64 {
    let sx = (1.0 + x * x).sqrt();
    let sy = (1.0 + y * y).sqrt();
    0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
}

/// ∫∫ x dx dy / (1 + x² + y²)² over [0, x] × [0, y], up to terms that cancel between corners.
fn moment_x(x: f64, y: f64) -> f64 {
    let s = (1.0 + x * x).sqrt();
    -(y / s).atan() / (2.0 * s)
}

/// Σ over the rectangle's corners of f with inclusion-exclusion signs.
fn over_rectangle(f: impl Fn(f64, f64) -> f64, x: [f64; 2], y: [f64; 2]) -> f64 {
    f(x[1], y[1]) - f(x[0], y[1]) - f(x[1], y[0]) + f(x[0], y[0])
}

/// ∫ cosθ dℓ along the straight plane edge at fixed coordinate `c` from `s0` to `s1` (the
/// tangent-plane length of G for an edge between plane texels).
fn edge_integral(c: f64, s0: f64, s1: f64) -> f64 {
    let c2 = 1.0 + c * c;
    let f = |s: f64| s / (c2 * (c2 + s * s).sqrt());
    f(s1) - f(s0)
}

/// ∫ ½ cos²θ_e dφ over the azimuths whose radial rays meet a side of the plane between its
/// middle and coordinate `s` along it (θ_e: the polar angle where the plane ends): the cosine
/// weight between the plane's edge and the horizon. With u = s/t and cos²θ_e = 1/(1 + t²(1 + u²)),
/// dφ = du/(1 + u²), the integrand splits into partial fractions.
fn stretched_weight(s: f64) -> f64 {
    let t = HALF_WIDTH;
    let u = s / t;
    let k = t / (1.0 + t * t).sqrt();
    0.5 * (u.atan() - k * (u * k).atan())
}

/// Steps per border texel of the numerical integrals over azimuth.
const AZIMUTH_STEPS: usize = 256;

impl Tables {
    pub fn new(resolution: usize, coverage: Coverage) -> Tables {
        let r = resolution;
        let n = r * r;
        let mut tables = Tables {
            resolution: r,
            weight: vec![0.0; n],
            rotation: vec![[0.0; 2]; n],
            right: vec![[0.0; 2]; n],
            down: vec![[0.0; 2]; n],
        };
        for j in 0..r {
            for i in 0..r {
                let x = [edge(i, r), edge(i + 1, r)];
                let y = [edge(j, r), edge(j + 1, r)];
                let t = j * r + i;
                tables.weight[t] = over_rectangle(cosine_integral, x, y);
                let mx = over_rectangle(moment_x, x, y);
                let my = over_rectangle(|a, b| moment_x(b, a), x, y);
                tables.rotation[t] = [-my, mx];
                if i + 1 < r {
                    tables.right[t] = [edge_integral(x[1], y[0], y[1]), 0.0];
                }
                if j + 1 < r {
                    tables.down[t] = [0.0, edge_integral(y[1], x[0], x[1])];
                }
            }
        }
        match coverage {
            Coverage::Plane => {}
            Coverage::Stretch => tables.stretch_border(),
            Coverage::Lc04 => {
                let scale = PI / tables.weight.iter().sum::<f64>();
                tables.scale(scale);
            }
        }
        tables
    }

    fn scale(&mut self, s: f64) {
        for t in 0..self.weight.len() {
            self.weight[t] *= s;
            for v in [
                &mut self.rotation[t],
                &mut self.right[t],
                &mut self.down[t],
            ] {
                v[0] *= s;
                v[1] *= s;
            }
        }
    }

    /// Give each border texel the directions from the plane's edge to the horizon along the
    /// azimuths of its stretch of edge, and run the edges between border texels to the horizon.
    fn stretch_border(&mut self) {
        let r = self.resolution;
        // The four sides as (texel of step k, point on the square at parameter s).
        type Side = (fn(usize, usize) -> (usize, usize), fn(f64) -> (f64, f64));
        let sides: [Side; 4] = [
            (|k, r| (r - 1, k), |s| (HALF_WIDTH, s)),
            (|k, _| (0, k), |s| (-HALF_WIDTH, s)),
            (|k, r| (k, r - 1), |s| (s, HALF_WIDTH)),
            (|k, _| (k, 0), |s| (s, -HALF_WIDTH)),
        ];
        for (texel, point) in sides {
            for k in 0..r {
                let (i, j) = texel(k, r);
                let (ax, ay) = point(edge(k, r));
                let (bx, by) = point(edge(k + 1, r));
                let phi0 = ay.atan2(ax);
                let mut dphi = by.atan2(bx) - phi0;
                if dphi > PI {
                    dphi -= 2.0 * PI;
                } else if dphi < -PI {
                    dphi += 2.0 * PI;
                }
                let step = dphi.abs() / AZIMUTH_STEPS as f64;
                let weight = stretched_weight(edge(k + 1, r)) - stretched_weight(edge(k, r));
                let mut rotation = [0.0; 2];
                for s in 0..AZIMUTH_STEPS {
                    let phi = phi0 + dphi * (s as f64 + 0.5) / AZIMUTH_STEPS as f64;
                    let m = phi.cos().abs().max(phi.sin().abs());
                    let theta_e = (HALF_WIDTH / m).atan();
                    // ∫ sin²θ dθ from θ_e to π/2, times (−sin φ, cos φ).
                    let radial = 0.5 * (FRAC_PI_2 - theta_e) + 0.25 * (2.0 * theta_e).sin();
                    rotation[0] -= phi.sin() * radial * step;
                    rotation[1] += phi.cos() * radial * step;
                }
                let t = j * r + i;
                self.weight[t] += weight;
                self.rotation[t][0] += rotation[0];
                self.rotation[t][1] += rotation[1];
            }
        }
        // Edges between neighbouring border texels continue along the meridian through their
        // shared corner, from the plane's edge to the horizon.
        let meridian = |x: f64, y: f64, toward: [f64; 2]| -> [f64; 2] {
            let rho = (x * x + y * y).sqrt();
            let sin_e = rho / (1.0 + rho * rho).sqrt();
            let phi = y.atan2(x);
            let e_phi = [-phi.sin(), phi.cos()];
            let sign = (e_phi[0] * toward[0] + e_phi[1] * toward[1]).signum();
            [sign * (1.0 - sin_e) * e_phi[0], sign * (1.0 - sin_e) * e_phi[1]]
        };
        for k in 0..r - 1 {
            let c = edge(k + 1, r);
            for (i, j, y) in [(k, 0, -HALF_WIDTH), (k, r - 1, HALF_WIDTH)] {
                let g = meridian(c, y, [1.0, 0.0]);
                let t = j * r + i;
                self.right[t][0] += g[0];
                self.right[t][1] += g[1];
            }
            for (i, j, x) in [(0, k, -HALF_WIDTH), (r - 1, k, HALF_WIDTH)] {
                let g = meridian(x, c, [0.0, 1.0]);
                let t = j * r + i;
                self.down[t][0] += g[0];
                self.down[t][1] += g[1];
            }
        }
    }

    /// The tables as the reduction shader reads them: per texel (W, Wr.x, Wr.y, 0) and
    /// (right.x, right.y, down.x, down.y).
    pub fn gpu_texels(&self) -> Vec<[[f32; 4]; 2]> {
        (0..self.weight.len())
            .map(|t| {
                let (r, d) = (self.right[t], self.down[t]);
                [
                    [
                        self.weight[t] as f32,
                        self.rotation[t][0] as f32,
                        self.rotation[t][1] as f32,
                        0.0,
                    ],
                    [r[0] as f32, r[1] as f32, d[0] as f32, d[1] as f32],
                ]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stretched_weights_sum_to_pi_and_the_plane_alone_to_the_spec_fraction() {
        for r in [8, 16, 64] {
            let stretch: f64 = Tables::new(r, Coverage::Stretch).weight.iter().sum();
            assert!((stretch - PI).abs() < 1e-9, "R {r}: Σ W = {stretch}");
            let lc04: f64 = Tables::new(r, Coverage::Lc04).weight.iter().sum();
            assert!((lc04 - PI).abs() < 1e-12, "R {r}");
            let plane: f64 = Tables::new(r, Coverage::Plane).weight.iter().sum();
            // Spec 003 §6: a plane of half-width 2 holds 0.831 of the cosine-weighted sphere.
            assert!((plane / PI - 0.8312).abs() < 2e-4, "R {r}: {}", plane / PI);
        }
    }

    /// Midpoint sums of the integrands over a texel, against the closed forms.
    #[test]
    fn closed_form_texel_integrals_match_quadrature() {
        let r = 16;
        let tables = Tables::new(r, Coverage::Plane);
        let n = 200;
        for (i, j) in [(0, 0), (3, 11), (7, 8), (15, 2)] {
            let (x0, x1, y0, y1) = (edge(i, r), edge(i + 1, r), edge(j, r), edge(j + 1, r));
            let (dx, dy) = ((x1 - x0) / n as f64, (y1 - y0) / n as f64);
            let (mut w, mut rx, mut ry) = (0.0, 0.0, 0.0);
            for a in 0..n {
                for b in 0..n {
                    let x = x0 + (a as f64 + 0.5) * dx;
                    let y = y0 + (b as f64 + 0.5) * dy;
                    let f = dx * dy / (1.0 + x * x + y * y).powi(2);
                    w += f;
                    rx -= y * f;
                    ry += x * f;
                }
            }
            let t = j * r + i;
            assert!((w - tables.weight[t]).abs() < 1e-6 * w, "W ({i},{j})");
            assert!((rx - tables.rotation[t][0]).abs() < 1e-6, "Wr.x ({i},{j})");
            assert!((ry - tables.rotation[t][1]).abs() < 1e-6, "Wr.y ({i},{j})");
        }
    }

    #[test]
    fn a_constant_hemisphere_has_no_gradient() {
        for coverage in [Coverage::Stretch, Coverage::Plane, Coverage::Lc04] {
            let t = Tables::new(32, coverage);
            let sum = |v: &[[f64; 2]]| v.iter().fold([0.0, 0.0], |a, b| [a[0] + b[0], a[1] + b[1]]);
            let rot = sum(&t.rotation);
            assert!(rot[0].abs() < 1e-12 && rot[1].abs() < 1e-12, "{coverage:?}");
        }
    }

    /// The edge integral in closed form against a midpoint sum along the arc.
    #[test]
    fn plane_edge_integrals_match_quadrature() {
        let (c, s0, s1) = (0.75, -1.5, 0.25);
        let n = 20_000;
        let mut sum = 0.0;
        let ds = (s1 - s0) / n as f64;
        for k in 0..n {
            let s = s0 + (k as f64 + 0.5) * ds;
            let p = DVec3::new(c, s, 1.0);
            let w = p.normalize();
            let half = DVec3::new(0.0, 0.5 * ds, 0.0);
            let dw = (p + half).normalize() - (p - half).normalize();
            // cosθ · dℓ · (tangent-plane x component of m, m ∝ (1, 0, −c)).
            sum += w.z * dw.length() / (1.0 + c * c).sqrt();
        }
        let closed = edge_integral(c, s0, s1);
        assert!((sum - closed).abs() < 1e-8, "{sum} vs {closed}");
    }
}
