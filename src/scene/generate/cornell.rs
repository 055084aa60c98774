//! Cornell boxes with their published ceiling light: `cornell-area` (open front, the published
//! camera), `cornell-area-closed` (a front wall, the camera inside), `cornell-area-16` (every
//! surface and the light split 2x2 twice, as seed 004's subdivided enclosure), and seed 004's
//! `four-boxes` (four closed boxes in a 2x2 grid, the camera in one) and `four-boxes-4` (split
//! once). Geometry in millimetres from the Cornell University Program of Computer Graphics'
//! published measurements (public data), scaled to metres.

use glam::{Mat4, Vec3};

use super::builder::Builder;
use crate::error::InputError;
use crate::scene::{Camera, Scene};

/// Reflectances of the usual renderer test scenes (the published spectra as RGB).
const WHITE: Vec3 = Vec3::new(0.725, 0.71, 0.68);
const RED: Vec3 = Vec3::new(0.63, 0.065, 0.05);
const GREEN: Vec3 = Vec3::new(0.14, 0.45, 0.091);
/// The light's radiance in the usual test scenes (W/(m²·sr)).
const LIGHT: Vec3 = Vec3::new(17.0, 12.0, 4.0);
/// Millimetres to metres.
const SCALE: f32 = 0.001;

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// One box: walls, blocks and the ceiling light (130 x 105 mm, 0.1 mm below the ceiling,
/// facing down), with a front wall when `closed`; surfaces split `split` times 2x2.
fn cornell_box(b: &mut Builder, closed: bool, split: u32) {
    let white = b.material("white", WHITE, Vec3::ZERO);
    let red = b.material("red", RED, Vec3::ZERO);
    let green = b.material("green", GREEN, Vec3::ZERO);
    let light = b.material("light", Vec3::splat(0.78), LIGHT);
    let walls = [
        (
            [
                v(552.8, 0.0, 0.0),
                v(0.0, 0.0, 0.0),
                v(0.0, 0.0, 559.2),
                v(549.6, 0.0, 559.2),
            ],
            white,
        ),
        (
            [
                v(556.0, 548.8, 0.0),
                v(556.0, 548.8, 559.2),
                v(0.0, 548.8, 559.2),
                v(0.0, 548.8, 0.0),
            ],
            white,
        ),
        (
            [
                v(549.6, 0.0, 559.2),
                v(0.0, 0.0, 559.2),
                v(0.0, 548.8, 559.2),
                v(556.0, 548.8, 559.2),
            ],
            white,
        ),
        (
            [
                v(0.0, 0.0, 559.2),
                v(0.0, 0.0, 0.0),
                v(0.0, 548.8, 0.0),
                v(0.0, 548.8, 559.2),
            ],
            green,
        ),
        (
            [
                v(552.8, 0.0, 0.0),
                v(549.6, 0.0, 559.2),
                v(556.0, 548.8, 559.2),
                v(556.0, 548.8, 0.0),
            ],
            red,
        ),
    ];
    for (quad, material) in walls {
        b.quad(quad, material, split);
    }
    if closed {
        b.quad(
            [
                v(0.0, 0.0, 0.0),
                v(552.8, 0.0, 0.0),
                v(556.0, 548.8, 0.0),
                v(0.0, 548.8, 0.0),
            ],
            white,
            split,
        );
    }
    let short = [
        v(130.0, 165.0, 65.0),
        v(82.0, 165.0, 225.0),
        v(240.0, 165.0, 272.0),
        v(290.0, 165.0, 114.0),
        v(290.0, 0.0, 114.0),
        v(240.0, 0.0, 272.0),
        v(130.0, 0.0, 65.0),
        v(82.0, 0.0, 225.0),
    ];
    let tall = [
        v(423.0, 330.0, 247.0),
        v(265.0, 330.0, 296.0),
        v(314.0, 330.0, 456.0),
        v(472.0, 330.0, 406.0),
        v(472.0, 0.0, 406.0),
        v(314.0, 0.0, 456.0),
        v(423.0, 0.0, 247.0),
        v(265.0, 0.0, 296.0),
    ];
    // The published faces of each block (1-based, as in the OBJ data; the tall block's
    // bottom corners are listed in the order that makes the same faces the published ones).
    let faces = [
        [1, 2, 3, 4],
        [5, 4, 3, 6],
        [7, 1, 4, 5],
        [8, 2, 1, 7],
        [6, 3, 2, 8],
    ];
    for block in [short, tall] {
        for face in faces {
            b.quad(face.map(|i| block[i - 1]), white, split);
        }
    }
    b.quad(
        [
            v(343.0, 548.7, 227.0),
            v(343.0, 548.7, 332.0),
            v(213.0, 548.7, 332.0),
            v(213.0, 548.7, 227.0),
        ],
        light,
        split,
    );
}

/// The published camera: 35 mm focal length on 25 mm film, 39.31 degrees.
fn published_camera() -> Camera {
    Camera {
        position: v(278.0, 273.0, -800.0),
        target: v(278.0, 273.0, 0.0),
        up: Vec3::Y,
        vfov_deg: 39.31,
    }
}

/// Inside a closed box (offset by `at`), just behind its front wall, looking at the back.
fn inside_camera(at: Vec3) -> Camera {
    Camera {
        position: at + v(278.0, 273.0, 40.0),
        target: at + v(278.0, 273.0, 559.2),
        up: Vec3::Y,
        vfov_deg: 70.0,
    }
}

pub fn cornell_area(name: &str, closed: bool, split: u32) -> Result<Scene, InputError> {
    let mut b = Builder::default();
    cornell_box(&mut b, closed, split);
    let camera = if closed {
        inside_camera(Vec3::ZERO)
    } else {
        published_camera()
    };
    b.finish(name, SCALE, vec![], camera)
}

/// Seed 004's multiple enclosures: four closed boxes, each in its own quadrant of the ground
/// plane with 150 mm between them; the camera is in the first.
pub fn four_boxes(name: &str, split: u32) -> Result<Scene, InputError> {
    let mut b = Builder::default();
    let pitch = 706.0;
    for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
        b.set_transform(Some(Mat4::from_translation(v(i * pitch, 0.0, j * pitch))));
        cornell_box(&mut b, true, split);
    }
    b.set_transform(None);
    b.finish(name, SCALE, vec![], inside_camera(Vec3::ZERO))
}
