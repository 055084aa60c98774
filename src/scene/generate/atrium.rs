//! `atrium`: a procedural two-storey arcaded courtyard standing in for seed 003's Sibenik and
//! Sponza (not available here): a paved courtyard open to the sky, surrounded on four sides by
//! galleries of columns and round arches on two storeys, walls behind them, gallery floors and
//! roofs, and coloured hangings draped between the upper columns. Two lights, as the seed's
//! scenes had: a spot "sun" high above the open roof and a warm point light in a gallery. Its
//! size is a parameter: `atrium:D` tessellates columns, arches and hangings at detail D (1-16;
//! the default 5 gives about 230 000 triangles, triangles growing as D²).

use std::f32::consts::{PI, TAU};

use glam::Vec3;

use super::builder::Builder;
use crate::error::InputError;
use crate::scene::{Camera, Light, LightKind, Scene};

/// The default detail.
pub const DEFAULT_DETAIL: u32 = 5;
/// Largest detail accepted.
pub const MAX_DETAIL: u32 = 16;

/// Courtyard half-extents (m) to the column lines, storey height, column radius.
const HALF_X: f32 = 10.0;
const HALF_Z: f32 = 6.0;
const STOREY: f32 = 5.0;
const COLUMN_RADIUS: f32 = 0.3;
/// Gallery depth behind the columns.
const GALLERY: f32 = 3.0;
/// Columns along x and z (corners included).
const BAYS_X: usize = 10;
const BAYS_Z: usize = 6;

struct Materials {
    stone: u32,
    paving: u32,
    plaster: u32,
    hangings: [u32; 4],
}

/// A column: a cylinder of `segments` sides and `rings` bands from `y0` to `y1`.
fn column(b: &mut Builder, base: Vec3, height: f32, segments: u32, rings: u32, material: u32) {
    let ring = |k: u32| {
        let a = TAU * k as f32 / segments as f32;
        Vec3::new(a.cos(), 0.0, a.sin()) * COLUMN_RADIUS
    };
    for r in 0..rings {
        let (y0, y1) = (
            base.y + height * r as f32 / rings as f32,
            base.y + height * (r + 1) as f32 / rings as f32,
        );
        for k in 0..segments {
            let (p, q) = (ring(k), ring(k + 1));
            let at = |o: Vec3, y: f32| Vec3::new(base.x + o.x, y, base.z + o.z);
            // Outward: counter-clockwise seen from outside.
            b.triangle([at(p, y0), at(p, y1), at(q, y1)], material);
            b.triangle([at(p, y0), at(q, y1), at(q, y0)], material);
        }
    }
}

/// A round arch between columns at `a` and `b` (same height `y`), `thickness` deep across the
/// arcade: the intrados (underside) and both faces, `segments` steps.
fn arch(b: &mut Builder, a: Vec3, c: Vec3, y: f32, segments: u32, material: u32) {
    let centre = (a + c) * 0.5;
    let along = (c - a).normalize();
    let across = along.cross(Vec3::Y);
    let radius = 0.5 * (c - a).length() - COLUMN_RADIUS;
    let depth = COLUMN_RADIUS;
    let top = y + radius + 0.6;
    let point = |t: f32| {
        let angle = PI * (1.0 - t);
        Vec3::new(centre.x, y, centre.z)
            + along * (radius * angle.cos())
            + Vec3::Y * (radius * angle.sin())
    };
    for s in 0..segments {
        let (t0, t1) = (s as f32 / segments as f32, (s + 1) as f32 / segments as f32);
        let (p, q) = (point(t0), point(t1));
        let (f, k) = (across * depth, -across * depth);
        // The intrados, facing down and in.
        b.triangle([p + f, q + k, q + f], material);
        b.triangle([p + f, p + k, q + k], material);
        // Both spandrel faces, up to the arch's top line.
        for side in [f, k] {
            let (pt, qt) = (Vec3::new(p.x, top, p.z), Vec3::new(q.x, top, q.z));
            if side == f {
                b.triangle([p + side, qt + side, pt + side], material);
                b.triangle([p + side, q + side, qt + side], material);
            } else {
                b.triangle([p + side, pt + side, qt + side], material);
                b.triangle([p + side, qt + side, q + side], material);
            }
        }
    }
}

/// A hanging cloth from `a` to `b` at height `y`, `drop` long, sagging and waving.
fn hanging(b: &mut Builder, a: Vec3, c: Vec3, y: f32, drop: f32, split: u32, material: u32) {
    let n = split.max(1);
    let point = |u: f32, v: f32| {
        let across = (c - a).normalize().cross(Vec3::Y);
        let wave = 0.08 * (u * 6.0 * PI).sin() * v;
        let sag = 0.25 * (u * PI).sin() * (1.0 - v);
        a + (c - a) * u + Vec3::Y * (y - v * drop - sag) + across * wave
    };
    for j in 0..n {
        for i in 0..n {
            let (u0, u1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
            let (v0, v1) = (j as f32 / n as f32, (j + 1) as f32 / n as f32);
            let (p, q, r, s) = (point(u0, v0), point(u1, v0), point(u1, v1), point(u0, v1));
            b.triangle([p, q, r], material);
            b.triangle([p, r, s], material);
        }
    }
}

/// Column positions around the courtyard, corners once.
fn column_ring() -> Vec<Vec3> {
    let mut ring = Vec::new();
    for i in 0..BAYS_X {
        let x = -HALF_X + 2.0 * HALF_X * i as f32 / (BAYS_X - 1) as f32;
        ring.push(Vec3::new(x, 0.0, -HALF_Z));
        ring.push(Vec3::new(x, 0.0, HALF_Z));
    }
    for k in 1..BAYS_Z - 1 {
        let z = -HALF_Z + 2.0 * HALF_Z * k as f32 / (BAYS_Z - 1) as f32;
        ring.push(Vec3::new(-HALF_X, 0.0, z));
        ring.push(Vec3::new(HALF_X, 0.0, z));
    }
    ring
}

/// Neighbouring columns along each side, as (a, b) pairs.
fn bays() -> Vec<(Vec3, Vec3)> {
    let mut pairs = Vec::new();
    for z in [-HALF_Z, HALF_Z] {
        for i in 0..BAYS_X - 1 {
            let x = |i: usize| -HALF_X + 2.0 * HALF_X * i as f32 / (BAYS_X - 1) as f32;
            pairs.push((Vec3::new(x(i), 0.0, z), Vec3::new(x(i + 1), 0.0, z)));
        }
    }
    for x in [-HALF_X, HALF_X] {
        for k in 0..BAYS_Z - 1 {
            let z = |k: usize| -HALF_Z + 2.0 * HALF_Z * k as f32 / (BAYS_Z - 1) as f32;
            pairs.push((Vec3::new(x, 0.0, z(k)), Vec3::new(x, 0.0, z(k + 1))));
        }
    }
    pairs
}

fn structure(b: &mut Builder, m: &Materials) {
    let (ox, oz) = (HALF_X + GALLERY, HALF_Z + GALLERY);
    // Paving over the whole footprint, facing up.
    b.quad(
        [
            Vec3::new(-ox, 0.0, -oz),
            Vec3::new(-ox, 0.0, oz),
            Vec3::new(ox, 0.0, oz),
            Vec3::new(ox, 0.0, -oz),
        ],
        m.paving,
        4,
    );
    // Outer walls facing in, two storeys high.
    let h = 2.0 * STOREY + 1.0;
    let walls = [
        [
            Vec3::new(-ox, 0.0, -oz),
            Vec3::new(ox, 0.0, -oz),
            Vec3::new(ox, h, -oz),
            Vec3::new(-ox, h, -oz),
        ],
        [
            Vec3::new(ox, 0.0, oz),
            Vec3::new(-ox, 0.0, oz),
            Vec3::new(-ox, h, oz),
            Vec3::new(ox, h, oz),
        ],
        [
            Vec3::new(-ox, 0.0, oz),
            Vec3::new(-ox, 0.0, -oz),
            Vec3::new(-ox, h, -oz),
            Vec3::new(-ox, h, oz),
        ],
        [
            Vec3::new(ox, 0.0, -oz),
            Vec3::new(ox, 0.0, oz),
            Vec3::new(ox, h, oz),
            Vec3::new(ox, h, -oz),
        ],
    ];
    for wall in walls {
        b.quad(wall, m.plaster, 3);
    }
    // Gallery slabs (the upper floor and the roof), a frame around the open courtyard: their
    // undersides face down, their tops up.
    let (ix, iz) = (HALF_X - COLUMN_RADIUS, HALF_Z - COLUMN_RADIUS);
    for y in [STOREY + 0.8, 2.0 * STOREY + 0.8] {
        let strips = [
            (Vec3::new(-ox, y, -oz), Vec3::new(ox, y, -iz)),
            (Vec3::new(-ox, y, iz), Vec3::new(ox, y, oz)),
            (Vec3::new(-ox, y, -iz), Vec3::new(-ix, y, iz)),
            (Vec3::new(ix, y, -iz), Vec3::new(ox, y, iz)),
        ];
        for (lo, hi) in strips {
            let (a, c) = (lo, hi);
            b.quad(
                [
                    Vec3::new(a.x, y, a.z),
                    Vec3::new(c.x, y, a.z),
                    Vec3::new(c.x, y, c.z),
                    Vec3::new(a.x, y, c.z),
                ],
                m.stone,
                1,
            );
            let top = y + 0.3;
            b.quad(
                [
                    Vec3::new(a.x, top, a.z),
                    Vec3::new(a.x, top, c.z),
                    Vec3::new(c.x, top, c.z),
                    Vec3::new(c.x, top, a.z),
                ],
                m.stone,
                1,
            );
        }
    }
}

pub fn atrium(name: &str, detail: u32) -> Result<Scene, InputError> {
    if !(1..=MAX_DETAIL).contains(&detail) {
        return Err(InputError::new(format!(
            "atrium:{detail}: the detail must be in 1..={MAX_DETAIL}"
        )));
    }
    let mut b = Builder::default();
    let m = Materials {
        stone: b.material("stone", Vec3::new(0.62, 0.58, 0.52), Vec3::ZERO),
        paving: b.material("paving", Vec3::new(0.45, 0.42, 0.38), Vec3::ZERO),
        plaster: b.material("plaster", Vec3::new(0.75, 0.68, 0.55), Vec3::ZERO),
        hangings: [
            b.material("crimson", Vec3::new(0.6, 0.06, 0.08), Vec3::ZERO),
            b.material("azure", Vec3::new(0.08, 0.2, 0.6), Vec3::ZERO),
            b.material("emerald", Vec3::new(0.07, 0.45, 0.15), Vec3::ZERO),
            b.material("gold", Vec3::new(0.75, 0.55, 0.1), Vec3::ZERO),
        ],
    };
    structure(&mut b, &m);
    let (segments, rings) = (16 * detail, 4 * detail);
    for storey in 0..2 {
        let y = storey as f32 * (STOREY + 1.1);
        for base in column_ring() {
            column(
                &mut b,
                base + Vec3::Y * y,
                STOREY - 0.9,
                segments,
                rings,
                m.stone,
            );
        }
        for (a, c) in bays() {
            arch(&mut b, a, c, y + STOREY - 0.9, 12 * detail, m.stone);
        }
    }
    for (k, (a, c)) in bays().into_iter().enumerate() {
        if k % 2 == 0 {
            let material = m.hangings[(k / 2) % 4];
            hanging(&mut b, a, c, 2.0 * STOREY - 0.2, 2.2, 6 * detail, material);
        }
    }
    let sun = Light {
        position: Vec3::new(3.0, 40.0, -2.0),
        kind: LightKind::Spot {
            direction: Vec3::new(-0.15, -1.0, 0.1),
            cone_angle_deg: 25.0,
            penumbra_deg: 3.0,
        },
        flux: 8_000.0,
        color: Vec3::new(1.0, 0.95, 0.85),
    };
    let lamp = Light {
        position: Vec3::new(-HALF_X - 1.5, 3.5, 0.0),
        kind: LightKind::Point,
        flux: 800.0,
        color: Vec3::new(1.0, 0.75, 0.45),
    };
    let camera = Camera {
        position: Vec3::new(HALF_X - 1.0, 1.7, HALF_Z - 0.5),
        target: Vec3::new(-HALF_X, 4.0, -HALF_Z + 1.0),
        up: Vec3::Y,
        vfov_deg: 65.0,
    };
    b.finish(name, 1.0, vec![sun, lamp], camera)
}
