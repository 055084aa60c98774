//! Radiosity (seed 004) on lavapipe with validation on: the GPU's progressive refinement
//! against the f64 Gauss–Seidel solve on the same elements, analytic form factors through both
//! item-buffer projections, energy bounds per shot, a closed box's closed form, and the
//! importance- and perspective-driven modes' equivalences with progressive refinement.

mod common;

use glam::{DVec3, Vec3};
use vkgi::gi::radiosity::camera::{CameraView, MAX_FOV_DEG};
use vkgi::gi::radiosity::cpu;
use vkgi::gi::radiosity::elements::{Density, Elements};
use vkgi::gi::radiosity::solver::{Mode, ShotState, Solver, SolverOptions};
use vkgi::gpu::Gpu;
use vkgi::render::targets::Eye;
use vkgi::scene::{Camera, Material, Mesh, Scene};

fn options(hemicube: bool, locations: u32) -> SolverOptions {
    SolverOptions {
        mode: Mode::Pr,
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

#[test]
fn a_device_without_subgroup_arithmetic_is_refused_in_one_line() {
    let mut gpu = common::gpu();
    // The stats pass sums each surface in a subgroup: without the operations it cannot be built.
    gpu.info.compute_subgroup_arithmetic = false;
    let scene = Scene::load("cornell-area").unwrap();
    let elements = Elements::bake(&scene, Density::Budget(100), &|_| {});
    let error = match Solver::new(&gpu, &scene, elements, options(false, 16)) {
        Ok(_) => panic!("a solver was built on a device without subgroup arithmetic"),
        Err(e) => format!("{e:#}"),
    };
    assert!(error.contains("subgroup arithmetic"), "{error}");
    assert!(!error.contains('\n'), "{error}");
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

/// Run `shots` shots one by one (after whatever `setup` records once); the shooter of each.
fn shooters(gpu: &Gpu, solver: &Solver, shots: u32) -> Vec<u32> {
    (0..shots)
        .map(|_| {
            gpu.one_shot(|rec| solver.record_shot(rec)).unwrap();
            solver.read_state(gpu).unwrap().shooter
        })
        .collect()
}

#[test]
fn with_uniform_importance_id_picks_the_shooters_pr_picks() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell-area").unwrap();
    let elements = Elements::bake(&scene, Density::Budget(300), &|_| {});
    let mut picked = Vec::new();
    for mode in [Mode::Pr, Mode::Id] {
        let solver = Solver::new(
            &gpu,
            &scene,
            elements.clone(),
            SolverOptions {
                mode,
                ..options(false, 16)
            },
        )
        .unwrap();
        gpu.one_shot(|rec| {
            solver.record_restart(rec, &scene.lights)?;
            solver.record_uniform_importance(rec);
            Ok(())
        })
        .unwrap();
        picked.push(shooters(&gpu, &solver, 40));
    }
    println!("pr: {:?}", picked[0]);
    assert!(
        picked[0]
            .iter()
            .collect::<std::collections::HashSet<_>>()
            .len()
            > 10
    );
    assert_eq!(picked[0], picked[1]);
    common::assert_no_validation_errors(&gpu);
}

/// A floor, a back wall lower than an emitter over the floor facing down (so nothing reaches
/// the emitter's top): a camera in front sees every side light reaches.
fn open_corner() -> Scene {
    let mut mesh = Mesh::default();
    let v = Vec3::new;
    quad(
        &mut mesh,
        [v(0., 0., 0.), v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.)],
        0,
    );
    quad(
        &mut mesh,
        [
            v(0., 0., 0.),
            v(1., 0., 0.),
            v(1., 0.75, 0.),
            v(0., 0.75, 0.),
        ],
        1,
    );
    quad(
        &mut mesh,
        [
            v(0.3, 0.8, 0.6),
            v(0.7, 0.8, 0.6),
            v(0.7, 0.8, 1.0),
            v(0.3, 0.8, 1.0),
        ],
        2,
    );
    let materials = vec![
        Material::diffuse("floor", Vec3::new(0.7, 0.6, 0.5)),
        Material::diffuse("wall", Vec3::new(0.3, 0.7, 0.4)),
        emitter(10.0),
    ];
    scene_of(mesh, materials)
}

fn camera_looking_at(scene: &Scene, target: Vec3, vfov_deg: f32) -> CameraView {
    let camera = Camera {
        position: Vec3::new(0.5, 0.4, 3.0),
        target,
        up: Vec3::Y,
        vfov_deg,
    };
    CameraView::of(&Eye {
        view_projection: camera.view_projection(4.0 / 3.0, scene.bounds_min, scene.bounds_max),
        position: camera.position,
    })
}

/// Shots in the id or pd mode with `camera` steering; pd's simulated view is `simulated`
/// first and the widest after `widen_after` shots. The shooters of 60 shots, the irradiance,
/// and which surfaces the first simulated view held.
fn view_driven(
    gpu: &Gpu,
    scene: &Scene,
    elements: &Elements,
    mode: Mode,
    camera: &CameraView,
    simulated: &CameraView,
    widen_after: u32,
) -> (Vec<u32>, Vec<DVec3>, Vec<bool>) {
    const SHOTS: u32 = 60;
    let solver = Solver::new(
        gpu,
        scene,
        elements.clone(),
        SolverOptions {
            mode,
            ..options(false, 16)
        },
    )
    .unwrap();
    gpu.one_shot(|rec| {
        solver.record_restart(rec, &scene.lights)?;
        solver.record_camera_importance(rec, camera)?;
        solver.record_visibility(rec, simulated, 1)
    })
    .unwrap();
    let first_view = solver.read_visible(gpu).unwrap();
    let mut picked = shooters(gpu, &solver, widen_after);
    gpu.one_shot(|rec| {
        solver.record_visibility(rec, &camera.widened(MAX_FOV_DEG), 2)?;
        solver.record_deliveries(rec, 64)
    })
    .unwrap();
    picked.extend(shooters(gpu, &solver, SHOTS - widen_after));
    let (direct, indirect) = solver.read_irradiance(gpu).unwrap();
    (picked, total(&direct, &indirect), first_view)
}

#[test]
fn pd_seeing_everything_equals_id_and_pd_seeing_part_converges_to_it() {
    let gpu = common::gpu();
    let scene = open_corner();
    let elements = Elements::bake(&scene, Density::Budget(400), &|_| {});
    assert_eq!(
        elements.surfaces.len(),
        3,
        "floor, wall and emitter are reached"
    );
    let camera = camera_looking_at(&scene, Vec3::new(0.5, 0.4, 0.3), 40.0);
    let wide = camera.widened(MAX_FOV_DEG);
    let run = |mode, simulated: &CameraView, widen_after| {
        view_driven(
            &gpu,
            &scene,
            &elements,
            mode,
            &camera,
            simulated,
            widen_after,
        )
    };
    let (id_shooters, id, _) = run(Mode::Id, &wide, 30);
    let (pd_shooters, pd, everything) = run(Mode::Pd, &wide, 30);
    assert_eq!(everything, [true; 3], "the widest view holds every surface");
    assert_eq!(id_shooters, pd_shooters);
    let same = relative_error(&elements, &pd, &id);
    println!("pd at {MAX_FOV_DEG} deg against id: relative error {same:.1e}");
    assert!(same < 1e-10, "{same}");

    // Narrow, on the wall alone: the floor's and emitter's share waits in the table until the
    // view widens, and then the solution converges to id's all the same.
    let narrow = camera_looking_at(&scene, Vec3::new(0.5, 0.6, 0.0), 10.0);
    let (narrow_shooters, pd_narrow, part) = run(Mode::Pd, &narrow, 20);
    println!("id shooters {id_shooters:?}\npd from a narrow view {narrow_shooters:?}");
    assert_ne!(
        narrow_shooters, id_shooters,
        "the narrow view changes the order"
    );
    let wall = elements
        .surfaces
        .iter()
        .position(|s| s.normal.z > 0.5)
        .unwrap();
    let in_view: Vec<usize> = (0..3).filter(|&s| part[s]).collect();
    assert_eq!(in_view, [wall], "only the wall is in the narrow view");
    let converged = relative_error(&elements, &pd_narrow, &id);
    println!(
        "pd from a 10 deg view, widened after 20 shots, against id: relative error {converged:.1e}"
    );
    assert!(converged < 1e-3, "{converged}");
    common::assert_no_validation_errors(&gpu);
}
