//! Seed 002's scene A, "boxes", as spec 002 §6 rebuilds it: the room [-4, 4]³ (red left wall,
//! green right wall, white others), a 2x2x2 box resting on the floor and a 2x4x2 one, the light
//! looking straight down from (0, 3.9, 3), the camera in the front wall at (0, 0, 4) looking at
//! the origin with a 125° field of view. One departure: the thesis's pure colours (white 1,
//! red (1, 0, 0), green (0, 1, 0)) are scaled by 0.8, so an unlimited-bounce reference of a room
//! that reflects everything does not take forever.

use glam::Vec3;

use super::builder::Builder;
use crate::error::InputError;
use crate::scene::{Camera, Light, LightKind, Scene};

/// The thesis's colours times this.
const ALBEDO: f32 = 0.8;

pub fn boxes(name: &str) -> Result<Scene, InputError> {
    let mut b = Builder::default();
    let white = b.material("white", Vec3::splat(ALBEDO), Vec3::ZERO);
    let red = b.material("red", Vec3::new(ALBEDO, 0.0, 0.0), Vec3::ZERO);
    let green = b.material("green", Vec3::new(0.0, ALBEDO, 0.0), Vec3::ZERO);
    let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Inward-facing walls, four vertices each.
    let walls = [
        (
            [
                c(-4., -4., -4.),
                c(-4., -4., 4.),
                c(4., -4., 4.),
                c(4., -4., -4.),
            ],
            white,
        ),
        (
            [
                c(-4., 4., -4.),
                c(4., 4., -4.),
                c(4., 4., 4.),
                c(-4., 4., 4.),
            ],
            white,
        ),
        (
            [
                c(-4., -4., -4.),
                c(4., -4., -4.),
                c(4., 4., -4.),
                c(-4., 4., -4.),
            ],
            white,
        ),
        (
            [
                c(-4., -4., 4.),
                c(-4., 4., 4.),
                c(4., 4., 4.),
                c(4., -4., 4.),
            ],
            white,
        ),
        (
            [
                c(-4., -4., -4.),
                c(-4., 4., -4.),
                c(-4., 4., 4.),
                c(-4., -4., 4.),
            ],
            red,
        ),
        (
            [
                c(4., -4., -4.),
                c(4., -4., 4.),
                c(4., 4., 4.),
                c(4., 4., -4.),
            ],
            green,
        ),
    ];
    for (quad, material) in walls {
        b.quad(quad, material, 0);
    }
    b.cuboid(c(1., -4., -1.), c(3., -2., 1.), white, false, 0);
    b.cuboid(c(-3., -4., -3.), c(-1., 0., -1.), white, false, 0);
    let light = Light {
        position: c(0.0, 3.9, 3.0),
        kind: LightKind::Spot {
            direction: Vec3::NEG_Y,
            cone_angle_deg: 62.5,
            penumbra_deg: 5.0,
        },
        flux: 200.0,
        color: Vec3::ONE,
    };
    let camera = Camera {
        position: c(0.0, 0.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        vfov_deg: 125.0,
    };
    b.finish(name, 1.0, vec![light], camera)
}
