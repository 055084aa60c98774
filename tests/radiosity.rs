//! Radiosity (seed 004) on lavapipe with validation on: the GPU's progressive refinement
//! against the f64 Gauss–Seidel solve on the same elements, analytic form factors through both
//! item-buffer projections, energy bounds per shot, and a closed box's closed form.

mod common;

use glam::{DVec3, Vec3};
use vkgi::gi::radiosity::cpu;
use vkgi::gi::radiosity::elements::{Density, Elements};
use vkgi::gi::radiosity::solver::{ShotState, Solver, SolverOptions};
use vkgi::gpu::Gpu;
use vkgi::scene::{Camera, Material, Mesh, Scene};

fn options(hemicube: bool, locations: u32) -> SolverOptions {
    SolverOptions {
        hemicube,
        resolution: 256,
        item_level: 2,
        locations,
        epsilon: 1e-6,
    }
}

/// Restart and run `shots` shots; the direct and indirect irradiance per element.
fn solve_gpu(gpu: &Gpu, scene: &Scene, solver: &Solver, shots: u32) -> (Vec<Vec3>, Vec<Vec3>) {
    gpu.one_shot(|rec| {
        solver.record_restart(rec, &scene.lights)?;
        for _ in 0..shots {
            solver.record_shot(rec)?;
        }
        Ok(())
    })
    .expect("shots");
    solver.read_irradiance(gpu).expect("readback")
}

/// Σ area |a − b|² / Σ area |b|² over the elements: relative squared error, area-weighted.
fn relative_error(elements: &Elements, a: &[DVec3], b: &[DVec3]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (i, e) in elements.elements.iter().enumerate() {
        let w = f64::from(e.area);
        num += w * (a[i] - b[i]).length_squared();
        den += w * b[i].length_squared();
    }
    num / den
}

fn total(direct: &[Vec3], indirect: &[Vec3]) -> Vec<DVec3> {
    direct
        .iter()
        .zip(indirect)
        .map(|(d, i)| (*d + *i).as_dvec3())
        .collect()
}

fn quad(mesh: &mut Mesh, [a, b, c, d]: [Vec3; 4], material: u32) {
    mesh.push_triangle([a, b, c], [Vec3::ZERO; 3], material);
    mesh.push_triangle([a, c, d], [Vec3::ZERO; 3], material);
}

fn scene_of(mesh: Mesh, materials: Vec<Material>) -> Scene {
    let (lo, hi) = mesh.bounds();
    Scene::new(
        "test".into(),
        mesh,
        materials,
        Vec::new(),
        Camera::framing(lo, hi),
    )
    .unwrap()
}

fn emitter(radiance: f32) -> Material {
    Material {
        emission: Vec3::splat(radiance),
        ..Material::diffuse("light", Vec3::ZERO)
    }
}

#[test]
fn the_gpu_solution_equals_the_f64_gauss_seidel_solve_on_a_coarse_cornell_box() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell-area").unwrap();
    let elements = Elements::bake(&scene, Density::Budget(300), &|_| {});
    let reference = cpu::solve(&scene, &elements, 1e-9, 500);
    let reference_total: Vec<DVec3> = reference
        .direct
        .iter()
        .zip(&reference.indirect)
        .map(|(d, i)| *d + *i)
        .collect();
    for hemicube in [false, true] {
        // Every texel its own shooting location, as the f64 solve's elements.
        let solver = Solver::new(&gpu, &scene, elements.clone(), options(hemicube, 64)).unwrap();
        let (direct, indirect) = solve_gpu(&gpu, &scene, &solver, 200);
        let state = solver.read_state(&gpu).unwrap();
        assert!(state.converged(), "{state:?}");
        let error = relative_error(&elements, &total(&direct, &indirect), &reference_total);
        println!(
            "hemicube {hemicube}: {} shots, relative error {error:.2e}",
            state.shots()
        );
        assert!(error < 0.01, "hemicube {hemicube}: {error}");
    }
    common::assert_no_validation_errors(&gpu);
}

/// Mean irradiance over the receiver's elements per unit emitted radiosity: its form factor to
/// the emitter.
fn form_factor_through_item_buffer(gpu: &Gpu, scene: &Scene, hemicube: bool) -> f64 {
    let elements = Elements::bake(scene, Density::Budget(800), &|_| {});
    let emitted = elements
        .surfaces
        .iter()
        .map(|s| s.emission.x)
        .fold(0.0, f32::max);
    let emitters = elements
        .surfaces
        .iter()
        .filter(|s| s.emission.x > 0.0)
        .count() as u32;
    let solver = Solver::new(gpu, scene, elements.clone(), options(hemicube, 1024)).unwrap();
    let (direct, _) = solve_gpu(gpu, scene, &solver, emitters);
    let (power, area) = elements
        .elements
        .iter()
        .zip(&direct)
        .filter(|(e, _)| elements.surfaces[e.surface as usize].emission == Vec3::ZERO)
        .fold((0.0, 0.0), |(p, a), (e, d)| {
            (p + f64::from(d.x * e.area), a + f64::from(e.area))
        });
    power / area / f64::from(emitted)
}

#[test]
fn analytic_form_factors_hold_through_both_item_buffers() {
    let gpu = common::gpu();
    // Two unit squares meeting at a right angle along an edge: F = 0.20004 (Hottel).
    let mut mesh = Mesh::default();
    let v = Vec3::new;
    quad(
        &mut mesh,
        [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
        0,
    );
    quad(
        &mut mesh,
        [v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.), v(0., 0., 0.)],
        1,
    );
    let perpendicular = scene_of(mesh, vec![emitter(1.0), Material::diffuse("r", Vec3::ZERO)]);
    // Two coaxial parallel discs (32-gons) of radius 1 at distance 1, facing each other:
    // F = (X − sqrt(X² − 4)) / 2 with X = 2 + h²/r² for equal radii r = the 32-gon's
    // area-equivalent radius.
    let mut mesh = Mesh::default();
    let sides = 32;
    let corner = |k: usize, z: f32| {
        let a = std::f32::consts::TAU * k as f32 / sides as f32;
        v(a.cos(), a.sin(), z)
    };
    for k in 0..sides {
        mesh.push_triangle(
            [v(0., 0., 0.), corner(k, 0.), corner(k + 1, 0.)],
            [Vec3::ZERO; 3],
            0,
        );
        mesh.push_triangle(
            [v(0., 0., 1.), corner(k + 1, 1.), corner(k, 1.)],
            [Vec3::ZERO; 3],
            1,
        );
    }
    let discs = scene_of(mesh, vec![emitter(1.0), Material::diffuse("r", Vec3::ZERO)]);
    let polygon_area = 0.5 * sides as f64 * (std::f64::consts::TAU / sides as f64).sin();
    let r2 = polygon_area / std::f64::consts::PI;
    let x = 2.0 + 1.0 / r2;
    let discs_exact = (x - (x * x - 4.0).sqrt()) / 2.0;
    for hemicube in [false, true] {
        for (name, scene, exact) in [
            ("perpendicular squares", &perpendicular, 0.20004),
            ("coaxial discs", &discs, discs_exact),
        ] {
            let f = form_factor_through_item_buffer(&gpu, scene, hemicube);
            println!("{name}, hemicube {hemicube}: {f:.5} (exact {exact:.5})");
            assert!(
                (f / exact - 1.0).abs() < 0.02,
                "{name}, hemicube {hemicube}: {f} vs {exact}"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn every_shot_conserves_energy() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell-area").unwrap();
    let elements = Elements::bake(&scene, Density::Budget(300), &|_| {});
    let max_albedo = elements
        .elements
        .iter()
        .map(|e| f64::from(e.albedo.max_element()))
        .fold(0.0, f64::max);
    let emitted = cpu::emitted_power(&scene, &elements);
    let solver = Solver::new(&gpu, &scene, elements.clone(), options(false, 16)).unwrap();
    gpu.one_shot(|rec| solver.record_restart(rec, &scene.lights))
        .unwrap();
    let mut before: Option<ShotState> = None;
    for shot in 0..40 {
        gpu.one_shot(|rec| solver.record_shot(rec)).unwrap();
        let state = solver.read_state(&gpu).unwrap();
        let (direct, indirect) = solver.read_irradiance(&gpu).unwrap();
        let received = cpu::received_power(&elements, &total(&direct, &indirect));
        let unshot = f64::from(state.power[0]);
        // The selection reports the power unshot before this shot, and the shooter's.
        if let Some(previous) = before {
            let shot_power = f64::from(previous.power[2]);
            let reflected = unshot - (f64::from(previous.power[0]) - shot_power);
            assert!(
                reflected <= max_albedo * shot_power * 1.001 + 1e-9,
                "shot {shot}: reflected {reflected} of {shot_power}"
            );
        }
        // Emitted power arrives at most once directly; what has been received, reflected
        // and not yet shot, is bounded by the emitted power summed over bounces.
        assert!(
            received * (1.0 - max_albedo) <= emitted * 1.001,
            "shot {shot}: received {received}, emitted {emitted}"
        );
        before = Some(state);
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_closed_uniform_box_converges_to_its_closed_form() {
    let gpu = common::gpu();
    // A unit cube, faces inward, every face emitting radiosity E = π·1 and reflecting ρ: every
    // element's irradiance is E / (1 − ρ) (the form factors of an enclosure sum to 1).
    let rho = 0.5;
    let mut mesh = Mesh::default();
    let v = Vec3::new;
    let faces = [
        [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)],
        [v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)],
        [v(0., 0., 0.), v(0., 0., 1.), v(0., 1., 1.), v(0., 1., 0.)],
        [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)],
        [v(0., 0., 0.), v(0., 1., 0.), v(1., 1., 0.), v(1., 0., 0.)],
        [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)],
    ];
    for [a, b, c, d] in faces {
        quad(&mut mesh, [d, c, b, a], 0);
    }
    let material = Material {
        emission: Vec3::ONE,
        ..Material::diffuse("wall", Vec3::splat(rho))
    };
    let scene = scene_of(mesh, vec![material]);
    let elements = Elements::bake(&scene, Density::Budget(600), &|_| {});
    assert_eq!(
        elements.surfaces.len(),
        6,
        "only the inner sides are reached"
    );
    let solver = Solver::new(&gpu, &scene, elements.clone(), options(false, 128)).unwrap();
    let (direct, indirect) = solve_gpu(&gpu, &scene, &solver, 150);
    let exact = std::f64::consts::PI / (1.0 - rho as f64);
    let (sum, area) = elements
        .elements
        .iter()
        .enumerate()
        .fold((0.0, 0.0), |(s, a), (i, e)| {
            (
                s + f64::from((direct[i].x + indirect[i].x) * e.area),
                a + f64::from(e.area),
            )
        });
    let mean = sum / area;
    println!("closed box: mean irradiance {mean:.4}, exact {exact:.4}");
    assert!((mean / exact - 1.0).abs() < 0.04, "{mean} vs {exact}");
    common::assert_no_validation_errors(&gpu);
}
