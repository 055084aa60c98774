//! Table 8.1 of the chapter regenerated (spec 003 §14): how far each way of covering the
//! directions a record's 126.87° plane misses (plane, [LC04], border stretching) puts its
//! irradiance from a Monte-Carlo integral over the whole hemisphere (`reference_side`²
//! cosine-weighted strata, one random direction in each), at surface points the scene's camera
//! sees (a square image, pixels drawn at random).
//!
//! The radiance field is the hemisphere pass's: direct light × albedo / π at the visible
//! surface, emission excluded, with exact visibility (a shadow ray per light) in place of shadow
//! maps. Hemispheres are sampled through their texel centres as the rasteriser samples them
//! (tests/irradiance_cache.rs holds the GPU's hemispheres to that sampling) and reduced with the
//! same tables as the GPU.

use glam::{DVec3, Vec2};

use super::cpu;
use super::tables::{Coverage, Tables};
use crate::reference::rng::random_float;
use crate::scene::bvh::Bvh;
use crate::scene::{Light, Scene};

/// The coverages in the order of Table 8.1's columns.
pub const COLUMNS: [Coverage; 3] = [Coverage::Plane, Coverage::Lc04, Coverage::Stretch];

/// What the study measured.
#[derive(Clone, Debug)]
pub struct CoverageStudy {
    /// Points whose reference irradiance was above zero (the others are skipped).
    pub points: usize,
    /// RMS of each point's relative error of Σ_channels E against the reference, per coverage
    /// in `COLUMNS` order.
    pub rms: [f64; 3],
    /// RMS of the absolute errors over the mean reference E (bright points weigh more).
    pub normalised_rms: [f64; 3],
}

/// One thread's sums.
#[derive(Default)]
struct Sums {
    relative: [f64; 3],
    absolute: [f64; 3],
    reference: f64,
    points: usize,
}

/// The study's sizes.
#[derive(Clone, Copy, Debug)]
pub struct StudySize {
    /// Camera pixels drawn (the chapter: 10 000).
    pub points: usize,
    /// Side of the hemisphere image (the chapter: 64).
    pub resolution: usize,
    /// The reference takes side² stratified cosine-weighted directions.
    pub reference_side: usize,
    /// Threads sharing the points.
    pub threads: usize,
}

/// Run the study on `scene` (lit by its lights; area lights by their raster samples).
pub fn coverage_study(scene: &Scene, size: StudySize) -> CoverageStudy {
    let bvh = Bvh::build(&scene.mesh);
    let field = Field {
        scene,
        bvh: &bvh,
        lights: scene.raster_lights(),
        near: 1e-4 * f64::from((scene.bounds_max - scene.bounds_min).length()),
    };
    let tables = COLUMNS.map(|c| Tables::new(size.resolution, c));
    let threads = size.threads.max(1);
    let sums: Vec<Sums> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let (field, tables) = (&field, &tables);
                s.spawn(move || {
                    let mut sums = Sums::default();
                    for i in (t..size.points).step_by(threads) {
                        let Some((p, n)) = field.camera_point(i as u32) else {
                            continue;
                        };
                        let Some((reference, e)) = field.irradiances(p, n, tables, size, i as u32)
                        else {
                            continue;
                        };
                        for (c, e) in e.into_iter().enumerate() {
                            let error = e - reference;
                            sums.absolute[c] += error * error;
                            sums.relative[c] += (error / reference).powi(2);
                        }
                        sums.reference += reference;
                        sums.points += 1;
                    }
                    sums
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().unwrap()).collect()
    });
    let points: usize = sums.iter().map(|s| s.points).sum();
    let n = points.max(1) as f64;
    let mean_reference = sums.iter().map(|s| s.reference).sum::<f64>() / n;
    let total = |part: fn(&Sums) -> &[f64; 3], c: usize| sums.iter().map(|s| part(s)[c]).sum::<f64>();
    CoverageStudy {
        points,
        rms: [0, 1, 2].map(|c| (total(|s| &s.relative, c) / n).sqrt()),
        normalised_rms: [0, 1, 2]
            .map(|c| (total(|s| &s.absolute, c) / n).sqrt() / mean_reference.max(f64::MIN_POSITIVE)),
    }
}

/// The scene as a record's hemisphere sees it.
struct Field<'a> {
    scene: &'a Scene,
    bvh: &'a Bvh,
    lights: Vec<Light>,
    /// The hemisphere camera's offset above the record and its near plane (as the GPU's).
    near: f64,
}

impl Field<'_> {
    /// The surface point and camera-facing normal seen through random pixel `i` of a square
    /// image, if any.
    fn camera_point(&self, i: u32) -> Option<(DVec3, DVec3)> {
        const SIDE: u32 = 1000;
        let camera = &self.scene.camera;
        let pixel = Vec2::new(
            random_float(0x7ab1e81, i, 0, 0) * SIDE as f32,
            random_float(0x7ab1e81, i, 0, 1) * SIDE as f32,
        );
        let dir = camera.ray_direction(pixel, SIDE, SIDE);
        let (p, n, _) = self.hit(camera.position.as_dvec3(), dir.as_dvec3(), 0.0)?;
        Some((p, n))
    }

    /// The closest surface along a ray past `t_min`: its point, normal facing the ray's origin,
    /// and the radiance it reflects (direct light × albedo / π).
    fn hit(&self, origin: DVec3, dir: DVec3, t_min: f64) -> Option<(DVec3, DVec3, [f64; 3])> {
        let surface = cpu::visible_surface(self.scene, self.bvh, origin, dir, t_min)?;
        let e = self.direct_irradiance(surface.position, surface.normal, surface.face);
        let l = [0, 1, 2].map(|c| surface.albedo[c] * e[c] / std::f64::consts::PI);
        Some((surface.position, surface.normal, l))
    }

    /// Direct irradiance at `p` from every light it sees (a shadow ray each).
    fn direct_irradiance(&self, p: DVec3, n: DVec3, face: DVec3) -> DVec3 {
        let origin = p + face * self.near;
        let mut e = DVec3::ZERO;
        for light in &self.lights {
            let incident = light.irradiance_at(p.as_vec3(), n.as_vec3()).as_dvec3();
            if incident == DVec3::ZERO {
                continue;
            }
            let to_light = light.position.as_dvec3() - origin;
            let distance = to_light.length();
            let blocked = self.bvh.occluded(
                origin.as_vec3(),
                (to_light / distance).as_vec3(),
                0.0,
                (distance * (1.0 - 1e-6)) as f32,
            );
            if !blocked {
                e += incident;
            }
        }
        e
    }

    /// The reference Σ_channels E at `p`, `n` (stratified Monte Carlo drawn with `seed`) and the
    /// record's under each coverage; None where the reference is zero.
    fn irradiances(
        &self,
        p: DVec3,
        n: DVec3,
        tables: &[Tables; 3],
        size: StudySize,
        seed: u32,
    ) -> Option<(f64, [f64; 3])> {
        let origin = p + n * self.near;
        // The hemisphere camera clips at depth `near` along the normal.
        let trace = |o: DVec3, dir: DVec3| {
            let t_min = self.near / dir.dot(n).max(1e-9);
            self.hit(o, dir, t_min)
                .map(|(q, _, l)| (l, (q - o).length()))
        };
        let reference =
            cpu::integrate_hemisphere(size.reference_side, Some(seed), origin, n, &trace);
        let reference: f64 = reference.iter().sum();
        if reference.is_nan() || reference <= 0.0 {
            return None;
        }
        let hemisphere = cpu::sample_hemisphere(size.resolution, origin, n, &trace);
        let e = tables
            .each_ref()
            .map(|t| cpu::reduce(t, &hemisphere, p, n).irradiance.iter().sum());
        Some((reference, e))
    }
}
