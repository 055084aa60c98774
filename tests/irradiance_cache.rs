//! Irradiance caching (seed 003) on lavapipe with validation on: the GPU reduction against the
//! f64 reduction of the same hemisphere, a constant hemisphere giving E = πL, the splat against
//! a brute-force gather over every record, and the gradients against finite differences of
//! brute-force hemisphere integrals.

mod common;

use glam::{DVec3, Vec3};
use vkgi::gi::irradiance_cache::cpu::{self, Hemisphere};
use vkgi::gi::irradiance_cache::passes::ZONE_PIXELS;
use vkgi::gi::irradiance_cache::records::{CacheState, GpuRecord};
use vkgi::gi::irradiance_cache::tables::{Coverage, Tables};
use vkgi::gi::irradiance_cache::{CacheSettings, IrradianceCache, Placement};
use vkgi::gi::registry::Setup;
use vkgi::gpu::Gpu;
use vkgi::reference::Bounces;
use vkgi::render::Frame;
use vkgi::render::runner::run_frames;
use vkgi::scene::bvh::Bvh;
use vkgi::scene::{Mesh, Scene};

fn settings(placement: Placement, accuracy: f64, per_frame: u32) -> CacheSettings {
    CacheSettings {
        weighting: cpu::Weighting {
            accuracy,
            smooth: true,
            normal_factor: 1.0,
            max_weight: 1e4,
        },
        coverage: Coverage::Stretch,
        hemisphere_size: 32,
        placement,
        capacity: 4096,
        per_frame,
        bounces: Bounces::Limited(1),
    }
}

fn read_records(gpu: &Gpu, ic: &IrradianceCache) -> (CacheState, Vec<GpuRecord>) {
    let state_bytes = gpu.read_buffer(&ic.passes.state).unwrap();
    let state: CacheState =
        bytemuck::pod_read_unaligned(&state_bytes[..std::mem::size_of::<CacheState>()]);
    let bytes = gpu.read_buffer(&ic.passes.records).unwrap();
    let records = bytemuck::cast_slice::<u8, GpuRecord>(&bytes)[..state.count as usize].to_vec();
    (state, records)
}

/// Run `frames` frames of the cache on the Cornell box at 64×48, indirect light only.
fn run(gpu: &Gpu, scene: &Scene, settings: CacheSettings, frames: u32) -> (Frame, IrradianceCache) {
    let mut frame = Frame::new(gpu, scene, common::indirect_only(64, 48)).unwrap();
    let mut ic = IrradianceCache::with(&Setup::new(gpu, scene), settings).unwrap();
    drop(run_frames(gpu, &mut frame, Some(&mut ic), 0, frames).unwrap());
    (frame, ic)
}

#[test]
fn the_gpu_reduction_matches_the_f64_reduction_of_the_same_hemisphere() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let s = settings(Placement::Scan, 0.3, 3);
    let (_frame, ic) = run(&gpu, &scene, s.clone(), 2);
    let (state, records) = read_records(&gpu, &ic);
    assert_eq!(
        state.end,
        state.first + 1,
        "scan placement adds one record a round"
    );
    let record = records[state.first as usize];
    let r = s.hemisphere_size as usize;
    let bytes = gpu.read_image(&ic.passes.hemisphere).unwrap();
    let texels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    let layer = &texels[..r * r];
    let hemisphere = Hemisphere {
        radiance: layer
            .iter()
            .map(|t| [0, 1, 2].map(|c| f64::from(t[c])))
            .collect(),
        distance: layer
            .iter()
            .map(|t| (t[3] > 0.0).then_some(f64::from(t[3])))
            .collect(),
    };
    assert!(
        hemisphere.radiance.iter().any(|l| l[0] > 0.0),
        "the record sees light"
    );
    let expected_record = record.to_record();
    let tables = Tables::new(r, s.coverage);
    let mut expected = cpu::reduce(
        &tables,
        &hemisphere,
        expected_record.position,
        expected_record.normal,
    );
    let zone = ZONE_PIXELS.map(f64::from);
    cpu::limit_radius(
        &mut expected,
        record.footprint(),
        s.weighting.accuracy,
        zone,
    );
    let got = record.to_record();
    let scale = expected.irradiance.iter().fold(0.0f64, |m, v| m.max(*v));
    for c in 0..3 {
        assert!(
            (got.irradiance[c] - expected.irradiance[c]).abs() < 1e-5 * scale,
            "E {c}"
        );
        assert!(
            (got.rotation[c] - expected.rotation[c]).length() < 1e-5 * scale,
            "∇r {c}"
        );
        let slope = expected.translation[c].length().max(scale);
        let error = (got.translation[c] - expected.translation[c]).length();
        assert!(error < 1e-4 * slope, "∇t {c}: {error} of {slope}");
    }
    assert!((got.harmonic - expected.harmonic).abs() < 1e-5 * expected.harmonic);
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_device_without_subgroup_arithmetic_is_refused_in_one_line() {
    let mut gpu = common::gpu();
    // The reduction sums each hemisphere in subgroups: without the operations it cannot run.
    gpu.info.compute_subgroup_arithmetic = false;
    let scene = Scene::load("cornell").unwrap();
    let settings = settings(Placement::Tiles, 0.5, 16);
    let error = match IrradianceCache::with(&Setup::new(&gpu, &scene), settings) {
        Ok(_) => panic!("an irradiance cache was built on a device without subgroup arithmetic"),
        Err(e) => format!("{e:#}"),
    };
    assert!(error.contains("subgroup arithmetic"), "{error}");
    assert!(!error.contains('\n'), "{error}");
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_constant_hemisphere_gives_pi_l_with_border_stretching() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let s = settings(Placement::Scan, 0.5, 1);
    let ic = IrradianceCache::with(&Setup::new(&gpu, &scene), s.clone()).unwrap();
    let record = GpuRecord {
        position_harmonic: [0.2, 0.0, 0.3, 0.0],
        normal_footprint: [0.0, 1.0, 0.0, 0.01],
        ..GpuRecord::default()
    };
    let state = CacheState {
        count: 1,
        first: 0,
        end: 1,
        ..CacheState::default()
    };
    let radiance = [0.7, 0.2, 1.5];
    gpu.write_buffer(&ic.passes.records, bytemuck::bytes_of(&record))
        .unwrap();
    gpu.write_buffer(&ic.passes.state, bytemuck::bytes_of(&state))
        .unwrap();
    gpu.one_shot(|rec| {
        let colour = [radiance[0], radiance[1], radiance[2], 0.4];
        rec.clear_image("constant hemisphere", &ic.passes.hemisphere, colour);
        ic.passes.record_reduce(rec, &s)
    })
    .unwrap();
    let (_, records) = read_records(&gpu, &ic);
    let got = records[0].to_record();
    for (c, l) in radiance.into_iter().enumerate() {
        let expected = std::f64::consts::PI * f64::from(l);
        assert!(
            (got.irradiance[c] - expected).abs() < 2e-6 * expected,
            "{c}"
        );
        assert!(got.rotation[c].length() < 1e-5 && got.translation[c].length() < 1e-5);
    }
    // R is the surroundings' distance, 0.4, inside the clamp [3, 64] × 0.01 / 0.5.
    assert!((got.harmonic - 0.4).abs() < 1e-6, "{}", got.harmonic);
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn the_splat_equals_a_brute_force_gather_over_every_record() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let s = settings(Placement::Tiles, 0.3, 48);
    let (frame, ic) = run(&gpu, &scene, s.clone(), 30);
    let (state, records) = read_records(&gpu, &ic);
    assert!(state.count > 20, "{} records", state.count);
    let records: Vec<cpu::Record> = records.iter().map(GpuRecord::to_record).collect();
    let view = frame.view();
    let positions = gpu.read_image(&view.gbuffer.position).unwrap();
    let positions: &[[f32; 4]] = bytemuck::cast_slice(&positions);
    let normals = gpu.read_image(&view.gbuffer.normal).unwrap();
    let normals: &[[u16; 4]] = bytemuck::cast_slice(&normals);
    let splat = gpu.read_image(&ic.passes.views[0].splat).unwrap();
    let splat: &[[f32; 4]] = bytemuck::cast_slice(&splat);
    let (mut covered, mut worst_weight, mut worst_irradiance) = (0, 0.0f64, 0.0f64);
    for (i, p) in positions.iter().enumerate() {
        if p[3] == 0.0 {
            continue;
        }
        let position = Vec3::new(p[0], p[1], p[2]).as_dvec3();
        let n = normals[i].map(common::half_to_f32);
        let normal = Vec3::new(n[0], n[1], n[2]).normalize().as_dvec3();
        let (sum, weight) = cpu::gather(&records, &s.weighting, position, normal);
        let gpu_weight = f64::from(splat[i][3]);
        worst_weight = worst_weight.max((gpu_weight - weight).abs() / weight.max(1.0));
        if weight > 0.0 {
            covered += 1;
            for c in 0..3 {
                let e = sum[c] / weight;
                let gpu_e = f64::from(splat[i][c]) / gpu_weight;
                worst_irradiance = worst_irradiance.max((gpu_e - e).abs() / e.max(1e-3));
            }
        }
    }
    // Placement has finished: every surface pixel is covered.
    let surface = positions.iter().filter(|p| p[3] != 0.0).count();
    assert_eq!(state.holes, 0, "{} records", state.count);
    assert_eq!(covered, surface);
    assert!(
        worst_weight < 1e-3,
        "Σw differs by {worst_weight} (relative)"
    );
    assert!(
        worst_irradiance < 1e-3,
        "Σ w E' / Σ w differs by {worst_irradiance}"
    );
    common::assert_no_validation_errors(&gpu);
}

/// A floor with a bright wall on one side and a block casting a distance boundary, every
/// surface of constant radiance (its albedo's red channel, as if emitted).
fn gradient_scene() -> (Mesh, Vec<[f64; 3]>) {
    let mut mesh = Mesh::default();
    let quad = |mesh: &mut Mesh, [a, b, c, d]: [Vec3; 4], material: u32| {
        mesh.push_triangle([a, b, c], [Vec3::ZERO; 3], material);
        mesh.push_triangle([a, c, d], [Vec3::ZERO; 3], material);
    };
    let v = Vec3::new;
    quad(
        &mut mesh,
        [
            v(-2.0, 0.0, -2.0),
            v(2.0, 0.0, -2.0),
            v(2.0, 0.0, 2.0),
            v(-2.0, 0.0, 2.0),
        ],
        0,
    );
    quad(
        &mut mesh,
        [
            v(1.0, 0.0, -2.0),
            v(1.0, 2.0, -2.0),
            v(1.0, 2.0, 2.0),
            v(1.0, 0.0, 2.0),
        ],
        1,
    );
    mesh.push_cuboid(v(-0.6, 0.0, -0.3), v(-0.2, 0.5, 0.3), 2);
    (mesh, vec![[0.1; 3], [2.0, 1.0, 0.5], [0.3, 0.6, 0.2]])
}

#[test]
fn gradients_match_finite_differences_of_brute_force_hemisphere_integrals() {
    let (mesh, radiance) = gradient_scene();
    let bvh = Bvh::build(&mesh);
    let trace = |origin: DVec3, dir: DVec3| {
        bvh.intersect(origin.as_vec3(), dir.as_vec3(), 1e-5, 1e30)
            .map(|hit| {
                (
                    radiance[mesh.materials[hit.triangle] as usize],
                    f64::from(hit.t),
                )
            })
    };
    let tables = Tables::new(128, Coverage::Stretch);
    let n = DVec3::Y;
    let (tangent, bitangent) = cpu::basis(n);
    let brute = |p: DVec3, normal: DVec3| cpu::integrate_hemisphere(1024, None, p, normal, &trace);
    for p in [DVec3::new(0.3, 1e-4, 0.1), DVec3::new(-0.1, 1e-4, 0.6)] {
        let hemisphere = cpu::sample_hemisphere(128, p, n, &trace);
        let record = cpu::reduce(&tables, &hemisphere, p, n);
        let e0 = brute(p, n);
        let h = 0.02;
        for axis in [tangent, bitangent] {
            let forward = brute(p + axis * h, n);
            let back = brute(p - axis * h, n);
            // n tilted toward `axis` by ±h radians.
            let turned = |s: f64| n * (s * h).cos() + axis * (s * h).sin();
            let up = brute(p, turned(1.0).normalize());
            let down = brute(p, turned(-1.0).normalize());
            for c in 0..3 {
                let fd = (forward[c] - back[c]) / (2.0 * h);
                let got = record.translation[c].dot(axis);
                let scale = e0[c];
                assert!(
                    (got - fd).abs() < 0.05 * scale + 0.15 * fd.abs(),
                    "∇t·{axis} channel {c} at {p}: tables {got}, finite differences {fd} (E {scale})"
                );
                let fd_rot = (up[c] - down[c]) / (2.0 * h);
                let turn = n.cross(turned(1.0).normalize());
                let predicted = turn.dot(record.rotation[c]) / h.sin();
                assert!(
                    (predicted - fd_rot).abs() < 0.02 * scale + 0.05 * fd_rot.abs(),
                    "∇r channel {c} at {p}: tables {predicted}, finite differences {fd_rot}"
                );
            }
        }
    }
}

#[test]
fn the_second_bounce_adds_the_snapshot_gathered_over_each_hemisphere() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let s = CacheSettings {
        bounces: Bounces::Limited(2),
        ..settings(Placement::Tiles, 0.5, 48)
    };
    let (_frame, ic) = run(&gpu, &scene, s.clone(), 40);
    let (state, records) = read_records(&gpu, &ic);
    assert_eq!(state.holes, 0, "placement settled");
    assert_eq!(state.bounce, 2, "{state:?}");
    assert_eq!(state.previous_count, state.count, "{state:?}");
    assert_eq!(
        state.refreshed, state.count,
        "every record refreshed: {state:?}"
    );
    assert_eq!(state.done, 1, "no third bounce is wanted: {state:?}");
    let bytes = gpu.read_buffer(&ic.passes.previous).unwrap();
    let first_bounce: Vec<cpu::Record> = bytemuck::cast_slice::<u8, GpuRecord>(&bytes)
        [..state.count as usize]
        .iter()
        .map(GpuRecord::to_record)
        .collect();

    // The snapshot is the first bounce: the cache of a one-bounce run, record for record.
    let one = CacheSettings {
        bounces: Bounces::Limited(1),
        ..s.clone()
    };
    let (_frame, single) = run(&gpu, &scene, one, 40);
    let (single_state, single_records) = read_records(&gpu, &single);
    assert_eq!(single_state.count, state.count);
    for (a, b) in single_records.iter().zip(&first_bounce) {
        let a = a.to_record();
        assert_eq!(a.position, b.position);
        for c in 0..3 {
            assert!((a.irradiance[c] - b.irradiance[c]).abs() <= 1e-6 * a.irradiance[c].max(1.0));
        }
    }

    // Each record's second bounce, recomputed on the CPU: its hemisphere traced through the BVH,
    // every texel's surface lit by the snapshot's gathered irradiance × albedo / π, reduced with
    // the same tables; the GPU's E rises by that much.
    let bvh = Bvh::build(&scene.mesh);
    let tables = Tables::new(s.hemisphere_size as usize, s.coverage);
    let diagonal = f64::from((scene.bounds_max - scene.bounds_min).length());
    let near = diagonal * 1e-4;
    // The hemisphere camera clips at depth `near` along the record's normal.
    let trace = |origin: DVec3, dir: DVec3, normal: DVec3| {
        let t_min = near / dir.dot(normal);
        let surface = cpu::visible_surface(&scene, &bvh, origin, dir, t_min)?;
        let (sum, weight) = cpu::gather(
            &first_bounce,
            &s.weighting,
            surface.position,
            surface.normal,
        );
        let e = if weight > 0.0 {
            sum.map(|v| v / weight)
        } else {
            [0.0; 3]
        };
        let l = [0, 1, 2].map(|c| surface.albedo[c] * e[c] / std::f64::consts::PI);
        Some((l, surface.distance))
    };
    let mut errors = Vec::new();
    for (k, (second, first)) in records.iter().zip(&first_bounce).enumerate() {
        let second = second.to_record();
        for c in 0..3 {
            assert!(
                second.irradiance[c] >= first.irradiance[c] * (1.0 - 1e-6),
                "record {k} channel {c}: {} after {}",
                second.irradiance[c],
                first.irradiance[c]
            );
        }
        let origin = first.position + first.normal * near;
        let r = s.hemisphere_size as usize;
        let hemisphere =
            cpu::sample_hemisphere(r, origin, first.normal, &|o, d| trace(o, d, first.normal));
        let added = cpu::reduce(&tables, &hemisphere, first.position, first.normal).irradiance;
        let scale = added.iter().fold(0.0f64, |m, v| m.max(*v));
        assert!(scale > 0.0, "record {k} gathers light");
        let error = (0..3)
            .map(|c| (second.irradiance[c] - first.irradiance[c] - added[c]).abs() / scale)
            .fold(0.0f64, f64::max);
        errors.push(error);
    }
    errors.sort_by(f64::total_cmp);
    let (median, worst) = (errors[errors.len() / 2], errors[errors.len() - 1]);
    assert!(errors.len() > 20, "{} records", errors.len());
    // Rasterisation and ray casting part at a few texels on silhouettes.
    assert!(
        median < 1e-5,
        "the second bounce differs by {median} (median)"
    );
    assert!(
        worst < 1e-2,
        "the second bounce differs by {worst} of its size"
    );
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn border_stretching_beats_lc04_beats_the_plain_plane_on_the_atrium() {
    use vkgi::gi::irradiance_cache::coverage_study::{StudySize, coverage_study};
    let scene = Scene::load("atrium").unwrap();
    // Table 8.1 at CI size; `cargo bench --bench ic_table81` runs the chapter's 10 000 points.
    let study = coverage_study(
        &scene,
        StudySize {
            points: 1000,
            resolution: 64,
            reference_side: 96,
            threads: 2,
        },
    );
    assert!(study.points > 500, "{} lit points", study.points);
    eprintln!(
        "Table 8.1 over {} points, RMS of relative errors: {:?}",
        study.points, study.rms
    );
    // The ladder is asserted on RMS error over the mean E (which reproduces the chapter's
    // values); per-point relative errors are dominated by a few dark points.
    let [plane, lc04, stretch] = study.normalised_rms;
    eprintln!("RMS error over mean E: plane {plane:.4}, lc04 {lc04:.4}, stretch {stretch:.4}");
    assert!(
        stretch < lc04 && lc04 < plane,
        "plane {plane}, lc04 {lc04}, stretch {stretch}"
    );
}
