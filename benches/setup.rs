//! CPU set-up costs, with criterion: LPV's transfer vectors and geometry (blocking) lattice,
//! the lattice's update when a dynamic object moves one frame, and the path tracer's BVH, on
//! the built-in scenes.
//!
//! cargo bench --bench setup

use criterion::{Criterion, criterion_group, criterion_main};
use vkgi::gi::lpv::geometry::{self, BlockingLobe};
use vkgi::gi::lpv::lattice::Lattice;
use vkgi::gi::lpv::transfer::TransferVectors;
use vkgi::scene::Scene;
use vkgi::scene::bvh::Bvh;

fn scene(name: &str) -> Scene {
    match Scene::load(name) {
        Ok(scene) => scene,
        Err(e) => panic!("{name}: {e}"),
    }
}

fn transfer_vectors(c: &mut Criterion) {
    c.bench_function("transfer vectors (20000 samples per neighbour)", |b| {
        b.iter(|| TransferVectors::compute(20_000, 0x000c_0ffe_e000))
    });
}

fn geometry_lattice(c: &mut Criterion) {
    let transfer = TransferVectors::compute(20_000, 0x000c_0ffe_e000);
    for name in ["cornell", "two-rooms"] {
        let scene = scene(name);
        for cells in [10, 32] {
            let lattice = match Lattice::fit(scene.bounds_min, scene.bounds_max, cells) {
                Ok(l) => l,
                Err(e) => panic!("{e}"),
            };
            for lobe in [
                BlockingLobe::TwoSided,
                BlockingLobe::Oriented,
                BlockingLobe::Visibility,
            ] {
                c.bench_function(&format!("geometry lattice {name} {cells} {lobe:?}"), |b| {
                    b.iter(|| geometry::build(&scene.mesh, &lattice, &transfer, lobe))
                });
            }
        }
    }
}

/// cornell-moving's tall block moves from frame 30 to 31 of its path: the cells it touched and
/// touches rebuilt, against the whole lattice rebuilt.
fn geometry_lattice_follow(c: &mut Criterion) {
    let transfer = TransferVectors::compute(20_000, 0x000c_0ffe_e000);
    let mut scene = scene("cornell-moving");
    scene.pose(30);
    let regions = vkgi::scene::dynamic::Moved::regions(&scene.pose(31));
    for cells in [16, 32, 64] {
        let lattice = match Lattice::fit(scene.bounds_min, scene.bounds_max, cells) {
            Ok(l) => l,
            Err(e) => panic!("{e}"),
        };
        for lobe in [BlockingLobe::TwoSided, BlockingLobe::Visibility] {
            let touched = geometry::touched_cells(&lattice, lobe, &regions);
            let rebuilt: usize = touched.iter().map(|t| t.count()).sum();
            let what = format!(
                "cornell-moving {cells} {lobe:?}: {rebuilt} of {} cells",
                lattice.cell_count()
            );
            c.bench_function(&format!("geometry lattice follows a move, {what}"), |b| {
                b.iter(|| {
                    geometry::touched_cells(&lattice, lobe, &regions)
                        .iter()
                        .map(|t| geometry::build_region(&scene.mesh, &lattice, &transfer, lobe, t))
                        .collect::<Vec<_>>()
                })
            });
            c.bench_function(
                &format!("geometry lattice rebuilt whole, cornell-moving {cells} {lobe:?}"),
                |b| b.iter(|| geometry::build(&scene.mesh, &lattice, &transfer, lobe)),
            );
        }
    }
}

fn bvh(c: &mut Criterion) {
    for name in ["cornell", "two-rooms"] {
        let scene = scene(name);
        c.bench_function(&format!("bvh {name}"), |b| {
            b.iter(|| Bvh::build(&scene.mesh))
        });
    }
}

criterion_group! {
    name = setup;
    config = Criterion::default().sample_size(10);
    targets = transfer_vectors, geometry_lattice, geometry_lattice_follow, bvh
}
criterion_main!(setup);
