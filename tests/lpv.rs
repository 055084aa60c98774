//! LPV and ILPV on lavapipe, validation on: the GPU kernels against the f64 CPU implementation,
//! energy bookkeeping, leaks, the ILPV steady state, and the hard cases.

mod common;

use glam::{DVec3, DVec4, Vec3};
use vkgi::gi::lpv::cpu::{self, StepParams};
use vkgi::gi::lpv::geometry::{BlockingLobe, GeometryLattice};
use vkgi::gi::lpv::lattice::CellOrder;
use vkgi::gi::lpv::projected;
use vkgi::gi::lpv::technique::{
    ChannelPlan, FarLattice, IlpvLookup, column_cells, shared_rows_possible,
};
use vkgi::gi::lpv::transfer::FaceScheme;
use vkgi::gi::lpv::two_scale;
use vkgi::gi::lpv::{Kernel, LookupFilter, Lpv, LpvSettings, Scheme};
use vkgi::gi::registry::Setup;
use vkgi::gi::shared::sh;
use vkgi::scene::Scene;

/// A SplitMix64 stream of uniform numbers in [0, 1).
fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Cells holding sums of 1-3 random positive cosine lobes of weight up to `scale`.
fn random_lattice(cells: usize, scale: f64, seed: u64) -> Vec<DVec4> {
    let mut r = rng(seed);
    (0..cells)
        .map(|_| {
            let lobes = 1 + (r() * 3.0) as usize;
            (0..lobes)
                .map(|_| {
                    let d = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(DVec3::Y);
                    sh::cosine_lobe(d) * (scale * r())
                })
                .sum()
        })
        .collect()
}

/// A geometry lattice of `lobe`'s kind: random SH lobes, or for the projected-area models 1-3
/// random surfaces per cell of area density up to `scale`, one-way or two-way at random.
fn random_geometry(lobe: BlockingLobe, cells: usize, scale: f64, seed: u64) -> GeometryLattice {
    if lobe.words_per_cell() == 1 {
        return GeometryLattice {
            lobe,
            words: random_lattice(cells, scale, seed),
        };
    }
    let mut r = rng(seed);
    if lobe == BlockingLobe::Visibility {
        let mut g = GeometryLattice::empty(lobe, cells);
        for cell in g.words.chunks_mut(4) {
            for k in 0..13 {
                cell[k / 4][k % 4] = f64::from(u8::from(r() < 0.3));
            }
        }
        return g;
    }
    let mut g = GeometryLattice::empty(lobe, cells);
    for cell in g.words.chunks_mut(projected::WORDS) {
        for _ in 0..1 + (r() * 3.0) as usize {
            let n = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(DVec3::Y);
            let outward = match (r() * 3.0) as u32 {
                0 => Some(n),
                1 => Some(-n),
                _ => None,
            };
            let a = scale * r();
            for (w, add) in cell.iter_mut().zip(projected::surface_words(n, outward)) {
                *w += add * a;
            }
        }
    }
    g
}

fn to_f32(cells: &[DVec4]) -> Vec<[f32; 4]> {
    cells.iter().map(|c| c.as_vec4().to_array()).collect()
}

/// Largest |gpu - cpu| relative to the largest |cpu| value of the lattice.
fn relative_error(gpu: &[[f32; 4]], cpu: &[DVec4]) -> f64 {
    let scale = cpu
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max);
    let worst = gpu
        .iter()
        .zip(cpu)
        .map(|(g, c)| (DVec4::from(g.map(f64::from)) - *c).abs().max_element())
        .fold(0.0, f64::max);
    worst / scale
}

/// The CPU f64 counterpart of `Lpv::record_propagation` for one channel: the final lattice and
/// the accumulation.
fn cpu_propagate(
    lpv: &Lpv,
    start: &[DVec4],
    geometry: &GeometryLattice,
    steps: usize,
) -> (Vec<DVec4>, Vec<DVec4>) {
    let faces = FaceScheme::compute();
    let s = &lpv.settings;
    let mut src = start.to_vec();
    let mut acc = start.to_vec();
    for step in 0..steps {
        let use_blocking = step > 0 || !s.first_step_unblocked;
        let dst = match s.scheme {
            Scheme::Ilpv => {
                let (mut absorption, mut scattering) = s.medium(lpv.lattice.cell_size);
                if s.clamp_compensation {
                    cpu::compensate_clamp(&mut src, &lpv.transfer, absorption, scattering);
                    (absorption, scattering) = (0.0, 0.0);
                }
                let p = StepParams {
                    absorption,
                    scattering,
                    use_blocking,
                };
                cpu::step_26(&lpv.lattice, &src, geometry, &lpv.transfer, p)
            }
            Scheme::Lpv => cpu::step_6(
                &lpv.lattice,
                &src,
                geometry,
                &faces,
                &lpv.transfer,
                use_blocking,
            ),
        };
        if s.scheme == Scheme::Lpv || step + 1 < steps {
            for (a, d) in acc.iter_mut().zip(&dst) {
                *a += *d;
            }
        }
        src = dst;
    }
    (src, acc)
}

#[test]
fn gpu_propagation_equals_the_f64_cpu_implementation() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let steps = 8;
    let mut worst = 0.0f64;
    // Every kernel does the same arithmetic per channel in the same order, whether a dispatch
    // carries one channel or three: the same bits, whichever runs.
    let mut first_kernel_results = std::collections::HashMap::new();
    let kernels = kernels_on(&gpu);
    let plans = [ChannelPlan::Separate, ChannelPlan::Fused];
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        for (kernel, plan) in kernels.iter().flat_map(|&k| plans.map(|p| (k, p))) {
            for (blocking, blocking_lobe) in [
                (false, BlockingLobe::Oriented),
                (true, BlockingLobe::Oriented),
                (true, BlockingLobe::Visibility),
                (true, BlockingLobe::TwoSided),
            ] {
                for lookup in [IlpvLookup::Accumulated, IlpvLookup::Final] {
                    if scheme == Scheme::Lpv && lookup == IlpvLookup::Final {
                        continue;
                    }
                    let settings = LpvSettings {
                        scheme,
                        lattice: 9,
                        iterations: steps as u32,
                        kernel: Some(kernel),
                        channels: Some(plan),
                        ilpv_lookup: lookup,
                        blocking_lobe,
                        scattering: if scheme == Scheme::Ilpv { 0.3 } else { 0.0 },
                        absorption: if scheme == Scheme::Ilpv { 0.2 } else { 0.0 },
                        extinction: vkgi::gi::lpv::Extinction::Physical,
                        ..LpvSettings::default()
                    };
                    let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), settings).unwrap();
                    // The column kernels split this lattice's columns into pieces (the test
                    // below has them walk whole columns).
                    let dims = lpv.lattice.dims;
                    assert!(column_cells(dims.to_array(), 1) < dims.z, "{dims}");
                    let cells = lpv.lattice.cell_count();
                    let starts = [1, 2, 3].map(|seed| random_lattice(cells, 1.0, seed));
                    let geometry = if blocking {
                        random_geometry(blocking_lobe, cells, 0.6, 9)
                    } else {
                        GeometryLattice::empty(blocking_lobe, cells)
                    };
                    lpv.load_lattices(&gpu, &starts.clone().map(|s| to_f32(&s)))
                        .unwrap();
                    lpv.load_geometry(&gpu, &geometry).unwrap();
                    gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
                    let result = lpv.read_result(&gpu).unwrap();
                    let case = format!("{scheme:?} {blocking} {blocking_lobe:?} {lookup:?}");
                    match first_kernel_results.get(&case) {
                        None => {
                            first_kernel_results.insert(case, result.clone());
                        }
                        Some(first) => {
                            assert!(
                                *first == result,
                                "{case}: {kernel:?} {plan:?} differs from tiled separate"
                            )
                        }
                    }
                    for c in 0..3 {
                        let (last, acc) = cpu_propagate(&lpv, &starts[c], &geometry, steps);
                        let expected = if scheme == Scheme::Ilpv && lookup == IlpvLookup::Final {
                            last
                        } else {
                            acc
                        };
                        let error = relative_error(&result[c], &expected);
                        worst = worst.max(error);
                        assert!(
                            error < 1e-4,
                            "{scheme:?} {kernel:?} blocking={blocking} {blocking_lobe:?} {lookup:?} channel {c}: relative error {error:e}"
                        );
                    }
                }
            }
        }
    }
    eprintln!("worst GPU/CPU relative difference after {steps} steps: {worst:e}");
    common::assert_no_validation_errors(&gpu);
}

/// Every kernel `gpu` runs: the shared rows where its subgroups lie along x.
fn kernels_on(gpu: &vkgi::gpu::Gpu) -> Vec<Kernel> {
    Kernel::ALL
        .into_iter()
        .filter(|kernel| kernel.runs_on(gpu))
        .collect()
}

/// Propagates random lattices (seeds `seeds`) through random two-sided geometry (seed
/// `geometry`; None: empty) on the GPU with `settings`, asserts each channel's accumulation
/// within 1e-4 of the f64 reference's (`case` names the run) and returns the GPU's result.
fn accumulate_random_lattices(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    settings: LpvSettings,
    (seeds, geometry): ([u64; 3], Option<u64>),
    case: &str,
) -> [Vec<[f32; 4]>; 3] {
    let steps = settings.iterations as usize;
    let mut lpv = Lpv::new(&Setup::new(gpu, scene), settings).unwrap();
    let cells = lpv.lattice.cell_count();
    let starts = seeds.map(|seed| random_lattice(cells, 1.0, seed));
    let lobe = BlockingLobe::TwoSided;
    let geometry = match geometry {
        Some(seed) => random_geometry(lobe, cells, 0.6, seed),
        None => GeometryLattice::empty(lobe, cells),
    };
    lpv.load_lattices(gpu, &starts.clone().map(|s| to_f32(&s)))
        .unwrap();
    lpv.load_geometry(gpu, &geometry).unwrap();
    gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
    let result = lpv.read_result(gpu).unwrap();
    for c in 0..3 {
        let (_, acc) = cpu_propagate(&lpv, &starts[c], &geometry, steps);
        let error = relative_error(&result[c], &acc);
        assert!(error < 1e-4, "{case} channel {c}: relative error {error:e}");
    }
    result
}

/// A frame's first step blocks nothing (the thesis), its own pipeline that reads no geometry;
/// `--block-first-step` blocks it too. Either way every step gives the f64 reference's light,
/// and the two differ where the geometry blocks. The unblocked first step through blocking
/// geometry gives the bits of a blocking step through empty geometry (a factor of 1).
#[test]
fn the_first_step_blocks_only_with_block_first_step() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        let run = |iterations, first_step_unblocked, geometry| {
            let settings = LpvSettings {
                scheme,
                lattice: 9,
                iterations,
                first_step_unblocked,
                ..LpvSettings::default()
            };
            let case = format!(
                "{scheme:?} {iterations} steps, first unblocked {first_step_unblocked}, geometry {geometry:?}"
            );
            accumulate_random_lattices(&gpu, &scene, settings, ([7, 8, 9], geometry), &case)
        };
        assert!(
            run(3, true, Some(3)) != run(3, false, Some(3)),
            "{scheme:?}: the first step's blocking changed nothing"
        );
        assert!(
            run(1, true, Some(3)) == run(1, false, None),
            "{scheme:?}: the unblocked first step's bits differ from a blocking step's through empty geometry"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// Where nothing reads a step's result (ILPV at λ_incr 0 and 2 steps: one step runs and its
/// light only goes into the accumulation, as in a two-scale near field), the step writes the
/// accumulation alone. With the clamp compensation (which applies the medium before the step)
/// and without it (the step applies it), every kernel and plan gives the f64 reference's
/// accumulation, and the same bits.
#[test]
fn a_step_whose_result_nothing_reads_accumulates_as_the_reference() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let plans = [ChannelPlan::Separate, ChannelPlan::Fused];
    for clamp_compensation in [true, false] {
        let mut first_result = None;
        for (kernel, plan) in kernels_on(&gpu).iter().flat_map(|&k| plans.map(|p| (k, p))) {
            let settings = LpvSettings {
                lattice: 9,
                iterations: 2,
                incremental: 0.0,
                kernel: Some(kernel),
                channels: Some(plan),
                clamp_compensation,
                scattering: 0.3,
                absorption: 0.2,
                extinction: vkgi::gi::lpv::Extinction::Physical,
                ..LpvSettings::default()
            };
            let case = format!("{kernel:?} {plan:?} compensation {clamp_compensation}");
            let result =
                accumulate_random_lattices(&gpu, &scene, settings, ([4, 5, 6], Some(7)), &case);
            match &first_result {
                None => first_result = Some(result),
                Some(first) => assert!(
                    *first == result,
                    "{kernel:?} {plan:?} compensation {clamp_compensation}: other bits than tiled separate"
                ),
            }
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// The column kernels' workgroups span a lattice's bundles along x (2x2 columns a thread: 16x4
/// for 24 cells across, 32x2 for 40; one column a thread, and the shared rows: 32x2 for both):
/// the same bits as the tiled kernel, whose workgroups are tiles, with the cells in the buffers in rows and in
/// columns.
#[test]
fn column_kernels_in_workgroups_wider_than_8x8_give_the_tiled_kernels_bits() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for (scheme, order) in [Scheme::Ilpv, Scheme::Lpv]
        .into_iter()
        .flat_map(|s| [CellOrder::Rows, CellOrder::Columns].map(|o| (s, o)))
    {
        for lattice in [24, 40] {
            let kernels = [
                Kernel::Tiled,
                Kernel::Column,
                Kernel::SingleColumn,
                Kernel::SharedRows,
            ];
            let results: Vec<_> = kernels_on(&gpu)
                .into_iter()
                .filter(|kernel| kernels.contains(kernel))
                .map(|kernel| {
                    let settings = LpvSettings {
                        scheme,
                        lattice,
                        iterations: 3,
                        kernel: Some(kernel),
                        channels: Some(ChannelPlan::Fused),
                        cell_order: Some(order),
                        lookup_filter: Some(LookupFilter::Texels),
                        ..LpvSettings::default()
                    };
                    let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), settings).unwrap();
                    let cells = lpv.lattice.cell_count();
                    let starts = [1, 2, 3].map(|seed| to_f32(&random_lattice(cells, 1.0, seed)));
                    let lobe = BlockingLobe::TwoSided;
                    lpv.load_lattices(&gpu, &starts).unwrap();
                    lpv.load_geometry(&gpu, &random_geometry(lobe, cells, 0.6, 9))
                        .unwrap();
                    gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
                    (lpv.lattice.dims, lpv.read_result(&gpu).unwrap())
                })
                .collect();
            let (dims, tiled) = &results[0];
            let [(_, column), (_, single)] = [&results[1], &results[2]];
            assert!(dims.x >= 24, "{scheme:?} {lattice}: {dims}");
            // Here each single-column thread walks its whole column (and skips the planes past
            // the lattice), at 40 each 2x2 bundle's thread too; the 9-cell lattice of the test
            // above splits columns into pieces.
            assert!(column_cells(dims.to_array(), 1) >= dims.z, "{dims}");
            if lattice == 40 {
                assert!(column_cells(dims.to_array(), 2) >= dims.z, "{dims}");
            }
            assert!(
                tiled == column,
                "{scheme:?} {order:?} {dims}: the column kernel's bits differ"
            );
            assert!(
                tiled == single,
                "{scheme:?} {order:?} {dims}: the single-column kernel's bits differ"
            );
            // The shared rows in whole subgroups (the 9-cell lattice above has a subgroup that
            // runs past the lattice in x).
            if let Some((_, shared)) = results.get(3) {
                assert!(
                    tiled == shared,
                    "{scheme:?} {order:?} {dims}: the shared-rows kernel's bits differ"
                );
            }
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// The lattices' buffers holding their cells in rows or in columns change where each cell lies,
/// not what is computed: the injection, the steps and the lookup give the same image bits
/// (fixed-point injection, whose sums do not depend on the threads' order).
#[test]
fn cells_in_rows_and_in_columns_give_the_same_image_bits() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        let [rows, columns] = [CellOrder::Rows, CellOrder::Columns].map(|order| {
            let settings = LpvSettings {
                scheme,
                injection: vkgi::gi::lpv::Injection::Fixed,
                kernel: Some(Kernel::SingleColumn),
                channels: Some(ChannelPlan::Fused),
                cell_order: Some(order),
                lookup_filter: Some(LookupFilter::Texels),
                ..ilpv(12)
            };
            common::render_gi(&gpu, &scene, settings, common::indirect_only(40, 30), 2)
        });
        assert!(common::mean(&rows) > 0.0, "{scheme:?}: no indirect light");
        assert!(rows == columns, "{scheme:?}: rows and columns differ");
    }
    // Two scales whose fields hold their cells in different orders (on a CPU device the near
    // field's single-column kernel walks whole columns of its 24³ lattice, the far field's
    // 5³ columns are split), read by one lookup: the bits of both in rows.
    let two_scales = |order: Option<CellOrder>| {
        let settings = LpvSettings {
            injection: vkgi::gi::lpv::Injection::Fixed,
            kernel: Some(Kernel::SingleColumn),
            channels: Some(ChannelPlan::Fused),
            cell_order: order,
            lookup_filter: Some(LookupFilter::Texels),
            ..ilpv(24)
        };
        let mut method = two_scale::TwoScale::new(&Setup::new(&gpu, &scene), settings, 5).unwrap();
        let orders = [method.near.cell_order(), method.far.cell_order()];
        let options = common::indirect_only(40, 30);
        (
            orders,
            common::render_with(&gpu, &scene, &mut method, options, 2),
        )
    };
    let (mixed_orders, mixed) = two_scales(None);
    let (rows_orders, rows) = two_scales(Some(CellOrder::Rows));
    if gpu.info.is_cpu() {
        assert_eq!(mixed_orders, [CellOrder::Columns, CellOrder::Rows]);
    }
    assert_eq!(rows_orders, [CellOrder::Rows; 2]);
    assert!(common::mean(&rows) > 0.0, "two scales: no indirect light");
    assert!(
        mixed == rows,
        "two scales: the fields' orders change the image"
    );
    common::assert_no_validation_errors(&gpu);
}

/// Propagate `start` (the same in R, G, B) one step at a time; returns the lattice after each.
fn steps_on_gpu(
    gpu: &vkgi::gpu::Gpu,
    lpv: &mut Lpv,
    start: &[DVec4],
    steps: usize,
) -> Vec<Vec<[f32; 4]>> {
    let mut current = to_f32(start);
    let mut out = Vec::new();
    for _ in 0..steps {
        lpv.load_lattices(gpu, &[current.clone(), current.clone(), current.clone()])
            .unwrap();
        gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
        current = lpv.read_result(gpu).unwrap()[0].clone();
        out.push(current.clone());
    }
    out
}

/// The relative energy change of each of `steps` GPU steps from `start`, one injected cell in
/// the lattice's middle.
fn energy_change_per_step(
    gpu: &vkgi::gpu::Gpu,
    lpv: &mut Lpv,
    start: &[DVec4],
    steps: usize,
) -> Vec<f64> {
    let mut previous = sh::energy(start[lpv.lattice.index(lpv.lattice.dims / 2)]);
    steps_on_gpu(gpu, lpv, start, steps)
        .iter()
        .map(|lattice| {
            let e = energy(lattice);
            let change = e / previous - 1.0;
            previous = e;
            change
        })
        .collect()
}

fn energy(cells: &[[f32; 4]]) -> f64 {
    cells
        .iter()
        .map(|c| sh::energy(DVec4::from(c.map(f64::from))))
        .sum()
}

/// One step at a time, final lattice read back, no blocking, no medium.
fn single_step_settings(scheme: Scheme, lattice: u32, clamp_compensation: bool) -> LpvSettings {
    LpvSettings {
        scheme,
        lattice,
        iterations: 1,
        ilpv_lookup: IlpvLookup::Final,
        clamp_compensation,
        ..LpvSettings::default()
    }
}

fn one_lobe(lpv: &Lpv) -> Vec<DVec4> {
    let mut cells = vec![DVec4::ZERO; lpv.lattice.cell_count()];
    let centre = lpv.lattice.dims / 2;
    cells[lpv.lattice.index(centre)] = sh::cosine_lobe(DVec3::new(0.3, 0.9, 0.2).normalize());
    cells
}

/// The VPLs of `lpv`'s RSM as the GPU rendered it, each with the light of its layer.
fn vpls_of(gpu: &vkgi::gpu::Gpu, scene: &Scene, lpv: &Lpv) -> Vec<cpu::Vpl> {
    let rsm = lpv.rsm().unwrap();
    let floats = |bytes: Vec<u8>| -> Vec<f32> { bytemuck::cast_slice(&bytes).to_vec() };
    let position = floats(gpu.read_image(&rsm.position).unwrap());
    let flux = floats(gpu.read_image(&rsm.flux).unwrap());
    let normal_bytes = gpu.read_image(&rsm.normal).unwrap();
    let normal: Vec<f32> = bytemuck::cast_slice::<u8, u16>(&normal_bytes)
        .iter()
        .map(|&h| common::half_to_f32(h))
        .collect();
    let (_, views) = vkgi::scene::gpu::shadow_views(scene, &scene.raster_lights(), 1024);
    let texels = (rsm.size * rsm.size) as usize;
    (0..texels * rsm.layers as usize)
        .filter(|&i| position[4 * i + 3] != 0.0)
        .map(|i| {
            let v = |data: &[f32]| {
                DVec3::new(
                    data[4 * i].into(),
                    data[4 * i + 1].into(),
                    data[4 * i + 2].into(),
                )
            };
            let origin = views[i / texels].origin;
            cpu::Vpl {
                position: v(&position),
                normal: v(&normal).normalize(),
                flux: v(&flux),
                light: DVec3::new(origin[0].into(), origin[1].into(), origin[2].into()),
            }
        })
        .collect()
}

#[test]
fn gpu_injection_equals_the_f64_cpu_injection_along_the_normal_and_toward_the_light() {
    use vkgi::gi::lpv::{InjectToward, Injection};
    let mut gpu = common::gpu();
    // Float atomics run inject_subgroup.comp where the device shuffles across narrow subgroups
    // (lavapipe's 8 lanes) and inject.comp where it does not: both, the second with the
    // capability cleared.
    let subgroups = gpu.info.compute_subgroup_shuffles;
    let injections = [
        (Injection::Float, subgroups),
        (Injection::Float, false),
        (Injection::Fixed, subgroups),
    ];
    // The spot-lit Cornell box, and a point light sealed in a cube (VPLs at its edges are where
    // the two ways differ most).
    let light = Vec3::new(0.16, 0.35, 0.14);
    let cube = (light - 0.1, light + 0.1);
    let scenes = [
        Scene::load("cornell").unwrap(),
        with_point_light(&Scene::load("cornell").unwrap(), light, 10.0, Some(cube)),
    ];
    for scene in &scenes {
        let ways = [(InjectToward::Normal, 0.5), (InjectToward::Light, 1.0)];
        let cases = ways
            .into_iter()
            .flat_map(|way| injections.map(|i| (way, i)));
        for ((toward, offset), (injection, subgroup_sums)) in cases {
            gpu.info.compute_subgroup_shuffles = subgroup_sums;
            // One frame of ILPV at λ 0 with one step: the lookup's lattice is the injection.
            let settings = LpvSettings {
                lattice: 16,
                rsm: 32,
                iterations: 1,
                incremental: 0.0,
                inject_offset: offset,
                inject_toward: toward,
                injection,
                ..LpvSettings::default()
            };
            let mut lpv = Lpv::new(&Setup::new(&gpu, scene), settings).unwrap();
            let mut frame =
                vkgi::render::Frame::new(&gpu, scene, common::indirect_only(16, 12)).unwrap();
            drop(vkgi::render::runner::run_frames(&gpu, &mut frame, Some(&mut lpv), 0, 1).unwrap());
            let injected = lpv.read_result(&gpu).unwrap();
            let vpls = vpls_of(&gpu, scene, &lpv);
            let expected = cpu::inject(&lpv.lattice, &vpls, f64::from(offset), toward);
            let error = (0..3)
                .map(|c| relative_error(&injected[c], &expected[c]))
                .fold(0.0, f64::max);
            eprintln!(
                "{} {toward:?} {injection:?} (subgroup sums {subgroup_sums}): {} VPLs, worst relative difference {error:.2e}",
                scene.lights.len(),
                vpls.len()
            );
            assert!(vpls.len() > 100);
            assert!(
                error < 1e-4,
                "{toward:?} {injection:?} {subgroup_sums}: {error}"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// Seed 000 §11.4: a CAVE's nodes must carry bit-identical lattices. Two logical devices (of
/// this driver) run eight ILPV frames (the light carried across frames, a moved light in between) with the fixed-point
/// injection and must agree to the bit; the float-atomic injection agrees with them to float
/// rounding.
#[test]
fn fixed_point_injection_gives_the_same_bits_on_two_devices_and_matches_float_atomics() {
    use vkgi::gi::lpv::Injection;
    let scene = Scene::load("cornell").unwrap();
    let settings = |injection| LpvSettings {
        lattice: 16,
        rsm: 64,
        injection,
        ..LpvSettings::default()
    };
    let run = |injection| {
        let gpu = common::gpu();
        let mut scene = scene.clone();
        let (mut lpv, _) = run_ilpv_frames(&gpu, &scene, settings(injection), 4);
        // Four more frames after the light moved (the blend carries the old light on).
        scene.lights[0].position += Vec3::new(0.05, 0.0, 0.02);
        let mut frame =
            vkgi::render::Frame::new(&gpu, &scene, common::indirect_only(16, 12)).unwrap();
        drop(vkgi::render::runner::run_frames(&gpu, &mut frame, Some(&mut lpv), 0, 4).unwrap());
        let lattices = lpv.read_result(&gpu).unwrap();
        common::assert_no_validation_errors(&gpu);
        lattices
    };
    let bits = |lattices: &[Vec<[f32; 4]>; 3]| -> Vec<u32> {
        lattices
            .iter()
            .flatten()
            .flatten()
            .map(|v| v.to_bits())
            .collect()
    };
    let (first, second) = (run(Injection::Fixed), run(Injection::Fixed));
    assert!(first.iter().flatten().flatten().any(|&v| v != 0.0));
    assert_eq!(
        bits(&first),
        bits(&second),
        "fixed point differs between devices"
    );
    let float = run(Injection::Float);
    let error = (0..3)
        .map(|c| {
            let exact: Vec<DVec4> = first[c]
                .iter()
                .map(|v| DVec4::from(v.map(f64::from)))
                .collect();
            relative_error(&float[c], &exact)
        })
        .fold(0.0, f64::max);
    eprintln!("float against fixed-point injection after 8 frames: {error:.2e}");
    assert!(error < 1e-5, "{error}");
}

#[test]
fn ilpv_steps_conserve_the_energy_of_one_injected_cell() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    // Compensated (the default): every step conserves energy to float precision.
    let mut lpv = Lpv::new(
        &Setup::new(&gpu, &scene),
        single_step_settings(Scheme::Ilpv, 24, true),
    )
    .unwrap();
    let start = one_lobe(&lpv);
    for (step, drift) in energy_change_per_step(&gpu, &mut lpv, &start, 10)
        .iter()
        .enumerate()
    {
        assert!(drift.abs() < 1e-3, "step {}: drift {drift:e}", step + 1);
    }
    // The thesis's global κ alone: the clamp adds energy to a fresh lobe for a few steps, then
    // the drift falls to the thesis's 1e-4..1e-6 per step.
    let mut lpv = Lpv::new(
        &Setup::new(&gpu, &scene),
        single_step_settings(Scheme::Ilpv, 24, false),
    )
    .unwrap();
    let drifts = energy_change_per_step(&gpu, &mut lpv, &start, 10);
    eprintln!("per-step energy change without clamp compensation: {drifts:?}");
    assert!(
        (0.01..0.02).contains(&drifts[0]),
        "first step {}",
        drifts[0]
    );
    assert!(drifts[6..].iter().all(|d| d.abs() < 1e-4), "{drifts:?}");
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn ilpv_scattering_without_absorption_conserves_energy() {
    // σa = 0, σs > 0: what a step scatters out it scatters back in. The thesis's γ = 1/26 kept
    // 0.695 of it, and its clamp on the sum cancelled more against negative transfers.
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for scattering in [5.0f32, 20.0, 200.0] {
        let settings = LpvSettings {
            scattering,
            ..single_step_settings(Scheme::Ilpv, 24, true)
        };
        let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), settings).unwrap();
        let (_, lambda_s) = lpv.settings.medium(lpv.lattice.cell_size);
        let start = one_lobe(&lpv);
        let drifts = energy_change_per_step(&gpu, &mut lpv, &start, 10);
        let worst = drifts.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        eprintln!(
            "σs {scattering}/m (λs {lambda_s:.4}): largest energy change in a step {worst:.1e}"
        );
        assert!(lambda_s > 0.1, "{lambda_s}");
        assert!(
            drifts.iter().all(|d| d.abs() < 1e-3),
            "σs {scattering}: {drifts:?}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn lpv_steps_move_exactly_the_flux_the_face_fractions_account_for() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let mut lpv = Lpv::new(
        &Setup::new(&gpu, &scene),
        single_step_settings(Scheme::Lpv, 16, true),
    )
    .unwrap();
    let faces = FaceScheme::compute();
    let mut before: Vec<DVec4> = one_lobe(&lpv);
    for step in 0..64 {
        let loaded = to_f32(&before);
        lpv.load_lattices(&gpu, &[loaded.clone(), loaded.clone(), loaded])
            .unwrap();
        gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
        // LPV's result is the accumulation (the loaded lattice plus this step): take the step out.
        let after = &lpv.read_result(&gpu).unwrap()[0];
        let moved: Vec<DVec4> = after
            .iter()
            .zip(&before)
            .map(|(a, b)| DVec4::from(a.map(f64::from)) - b.as_vec4().as_dvec4())
            .collect();
        let expected = cpu::face_fraction_flux(&lpv.lattice, &before, &faces);
        let got: f64 = moved.iter().map(|c| sh::energy(*c)).sum();
        assert!(
            (got - expected).abs() <= 1e-4 * expected.max(1e-30),
            "step {}: energy {got} vs face-fraction flux {expected}",
            step + 1
        );
        before = moved;
    }
    common::assert_no_validation_errors(&gpu);
}

fn ilpv(lattice: u32) -> LpvSettings {
    LpvSettings {
        lattice,
        ..LpvSettings::default()
    }
}

#[test]
fn async_sequential_and_fused_channel_plans_give_the_same_image() {
    use vkgi::render::SubmitPlan;
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let image = |submit, channels| {
        let options = vkgi::render::FrameOptions {
            submit,
            ..common::indirect_only(48, 36)
        };
        let settings = LpvSettings {
            channels: Some(channels),
            ..ilpv(10)
        };
        common::render_gi(&gpu, &scene, settings, options, 3)
    };
    // Three parts, R, G and B, in one command buffer and as a submission each; one part RGB.
    let sequential = image(SubmitPlan::Sequential, ChannelPlan::Separate);
    let asynchronous = image(SubmitPlan::Async, ChannelPlan::Separate);
    let fused = image(SubmitPlan::Async, ChannelPlan::Fused);
    assert!(common::mean(&sequential) > 0.0);
    // Injection sums RSM texels with float atomics, whose order the driver's threads decide, so
    // two runs of the same plan agree to rounding, not bit for bit: allow a few ulps of the sum.
    for (name, other) in [("async", &asynchronous), ("fused", &fused)] {
        let (worst, brightest) = common::worst_difference(other, &sequential);
        assert!(
            worst <= 1e-5 * brightest,
            "{name} differs from sequential by {worst} (brightest {brightest})"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn no_light_leaks_through_the_wall_between_the_two_rooms() {
    let gpu = common::gpu();
    let mut scene = Scene::load("two-rooms").unwrap();
    let rooms = [
        (Vec3::new(0.4, 1.7, 0.4), Vec3::new(3.5, 1.0, 3.0)),
        (Vec3::new(8.1, 1.7, 0.4), Vec3::new(5.0, 1.0, 3.0)),
    ];
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        for blocking_lobe in [
            BlockingLobe::TwoSided,
            BlockingLobe::Oriented,
            BlockingLobe::Visibility,
        ] {
            let settings = LpvSettings {
                scheme,
                lattice: 24,
                iterations: 16,
                blocking_lobe,
                ..LpvSettings::default()
            };
            let [lit, dark] = rooms.map(|(position, target)| {
                scene.camera.position = position;
                scene.camera.target = target;
                let options = common::indirect_only(64, 48);
                let image = common::render_gi(&gpu, &scene, settings.clone(), options, 8);
                assert!(image.iter().flatten().all(|v| v.is_finite()));
                common::mean(&image)
            });
            eprintln!(
                "{scheme:?} {blocking_lobe:?}: indirect light, lit room / dark room {lit:.5} / {dark:.6} ({:.2}%)",
                100.0 * dark / lit
            );
            assert!(
                dark < 0.01 * lit,
                "{scheme:?} {blocking_lobe:?} leaks: {dark} vs {lit}"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// Walls of a 24 x 8 x 8 lattice of unit cells.
#[derive(Clone, Copy, PartialEq)]
enum Walls {
    None,
    /// A closed room: six walls a quarter cell inside the lattice's faces.
    Room,
    /// One partition across the middle, the plane y = 4.5.
    Partition,
}

/// The accumulated light a beam running along +x (two lobes SH_cos(+x) at x = 1, in row
/// `beam_row`) delivers to the far quarter of a 24 x 8 x 8 lattice of unit cells (x >= 18).
fn light_along_walls(
    gpu: &vkgi::gpu::Gpu,
    scheme: Scheme,
    lobe: BlockingLobe,
    walls: Walls,
    beam_row: u32,
) -> f64 {
    let mut scene = Scene::load("cornell").unwrap();
    let size = Vec3::new(24.0, 8.0, 8.0);
    scene.bounds_min = Vec3::ZERO;
    scene.bounds_max = size;
    let settings = LpvSettings {
        scheme,
        lattice: 24,
        iterations: 32,
        blocking_lobe: lobe,
        ..LpvSettings::default()
    };
    let mut lpv = Lpv::new(&Setup::new(gpu, &scene), settings).unwrap();
    let lattice = lpv.lattice;
    assert_eq!(lattice.dims, size.as_uvec3());
    let mut mesh = vkgi::scene::Mesh::default();
    // The plane of `axis` at `at`, across the lattice.
    let mut plane = |axis: usize, at: f32| {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let corner = |a: f32, b: f32| {
            let mut p = Vec3::ZERO;
            p[axis] = at;
            p[u] = a * size[u];
            p[v] = b * size[v];
            p
        };
        let corners = [
            corner(0.0, 0.0),
            corner(1.0, 0.0),
            corner(1.0, 1.0),
            corner(0.0, 1.0),
        ];
        for tri in [[0, 1, 2], [0, 2, 3]] {
            mesh.push_triangle(tri.map(|i| corners[i]), [Vec3::ZERO; 3], 0);
        }
    };
    match walls {
        Walls::None => {}
        Walls::Room => {
            for axis in 0..3 {
                plane(axis, 0.25);
                plane(axis, size[axis] - 0.25);
            }
        }
        Walls::Partition => plane(1, 4.5),
    }
    let geometry = vkgi::gi::lpv::geometry::build(&mesh, &lattice, &lpv.transfer, lobe);
    let mut beam = vec![DVec4::ZERO; lattice.cell_count()];
    for z in 3..5 {
        beam[lattice.index(glam::UVec3::new(1, beam_row, z))] = sh::cosine_lobe(DVec3::X);
    }
    let beam = to_f32(&beam);
    lpv.load_lattices(gpu, &[beam.clone(), beam.clone(), beam])
        .unwrap();
    lpv.load_geometry(gpu, &geometry).unwrap();
    gpu.one_shot(|rec| lpv.record_propagation(rec)).unwrap();
    let result = lpv.read_result(gpu).unwrap();
    let mut far = 0.0;
    for z in 0..8 {
        for y in 0..8 {
            for x in 18..24 {
                let c = result[0][lattice.index(glam::UVec3::new(x, y, z))];
                far += sh::energy(DVec4::from(c.map(f64::from)));
            }
        }
    }
    far
}

#[test]
fn light_running_along_a_rooms_walls_is_not_blocked_by_them() {
    // A closed room filling the lattice, and a beam running along its floor one row up. With
    // oriented blocking the walls face the void outside and only stop light leaving the room,
    // which leaves the lattice without them too; with visibility no segment between two cell
    // centres inside the room crosses them. The thesis's two-sided lobe blocks every transfer out
    // of the walls' cells alike, and so does the two-way projected area.
    let gpu = common::gpu();
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        let open = light_along_walls(&gpu, scheme, BlockingLobe::Oriented, Walls::None, 1);
        let mut losses = Vec::new();
        for lobe in [
            BlockingLobe::Oriented,
            BlockingLobe::Projected,
            BlockingLobe::Visibility,
            BlockingLobe::TwoSided,
            BlockingLobe::Front,
            BlockingLobe::Back,
        ] {
            let along = light_along_walls(&gpu, scheme, lobe, Walls::Room, 1);
            losses.push((lobe, 1.0 - along / open));
        }
        // For the record: a partition across the middle, next to the beam (row 3). Blocking
        // that stops light crossing a wall both ways takes most of it here, because 2-band
        // lobes spread a quarter of a beam's light sideways each step, and without the wall
        // that light spreads back.
        let open_middle = light_along_walls(&gpu, scheme, BlockingLobe::Oriented, Walls::None, 3);
        let middle = light_along_walls(&gpu, scheme, BlockingLobe::Oriented, Walls::Partition, 3);
        eprintln!(
            "{scheme:?}: light lost to the room's walls: {losses:.4?}; to a partition beside the beam: {:.4}",
            1.0 - middle / open_middle
        );
        for (lobe, loss) in &losses[..3] {
            if *lobe != BlockingLobe::Projected {
                assert!(
                    loss.abs() <= 0.05,
                    "{scheme:?} {lobe:?}: the walls take {loss}"
                );
            }
        }
        assert!(losses[3].1 > 0.2, "{losses:?}");
    }
    common::assert_no_validation_errors(&gpu);
}

/// `base` lit by one point light at `light` instead of its own lights, with a closed white
/// box (`min`..`max`, six faces) added when given.
fn with_point_light(
    base: &Scene,
    light: Vec3,
    flux: f32,
    sealed_in: Option<(Vec3, Vec3)>,
) -> Scene {
    let mut mesh = base.mesh.clone();
    let white = base
        .materials
        .iter()
        .position(|m| m.name == "white")
        .unwrap() as u32;
    if let Some((min, max)) = sealed_in {
        mesh.push_cuboid(min, max, white);
    }
    let point = vkgi::scene::Light {
        position: light,
        kind: vkgi::scene::LightKind::Point,
        flux,
        color: Vec3::ONE,
    };
    Scene::new(
        base.name.clone(),
        mesh,
        base.materials.clone(),
        vec![point],
        base.camera,
    )
    .unwrap()
}

/// The indirect light a point light sealed in a box leaks, over the same light's indirect light
/// with the box open, seen from the scene camera, per lattice.
fn sealed_light_leaks(
    gpu: &vkgi::gpu::Gpu,
    base: &Scene,
    light: Vec3,
    sealed_in: (Vec3, Vec3),
    open_light: Vec3,
    lattices: &[u32],
    settings: &LpvSettings,
) -> Vec<(u32, f64)> {
    let sealed = with_point_light(base, light, 10.0, Some(sealed_in));
    let open = with_point_light(base, open_light, 10.0, None);
    lattices
        .iter()
        .map(|&lattice| {
            let settings = LpvSettings {
                lattice,
                rsm: 64,
                ..settings.clone()
            };
            // The mean over the pixels that do not see the box (its outside faces read the
            // cells that straddle its walls).
            let box_triangles = base.mesh.triangle_count();
            let mean = |scene: &Scene| {
                let (w, h) = (32, 24);
                let image =
                    common::render_gi(gpu, scene, settings.clone(), common::indirect_only(w, h), 6);
                let kept: Vec<[f32; 3]> = image
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| {
                        let pixel = glam::Vec2::new(
                            (i % w as usize) as f32 + 0.5,
                            (i / w as usize) as f32 + 0.5,
                        );
                        let dir = scene.camera.ray_direction(pixel, w, h);
                        scene
                            .mesh
                            .intersect(scene.camera.position, dir, 1e-4, 1e9)
                            .is_some_and(|hit| hit.triangle < box_triangles)
                    })
                    .map(|(_, p)| *p)
                    .collect();
                common::mean(&kept)
            };
            (lattice, mean(&sealed) / mean(&open))
        })
        .collect()
}

/// Whether `leaks` (finest lattice first) fall as the lattice refines.
fn falls_with_refinement(leaks: &[(u32, f64)]) -> bool {
    leaks.windows(2).all(|w| w[0].1 < w[1].1)
}

#[test]
fn a_light_sealed_in_a_box_leaks_under_two_percent_with_visibility_blocking_and_none_injected_toward_it()
 {
    let gpu = common::gpu();
    // A 100 mm cube in the Cornell box (559 mm across: 24 cells of 23 mm put 4.3 across it)
    // with a point light at its centre; open, the same light hangs there without the cube.
    let cornell = Scene::load("cornell").unwrap();
    let centre = Vec3::new(0.42, 0.40, 0.12);
    let cube = (centre - 0.05, centre + 0.05);
    let leaks = |settings: &LpvSettings, lattices: &[u32]| {
        sealed_light_leaks(&gpu, &cornell, centre, cube, centre, lattices, settings)
    };
    // Visibility blocking is watertight; the first step of a frame is blocked too (else it moves
    // light out of the cells whose centres the walls pass near), with VPLs injected a cell in
    // front of their surface so that it does not block their own light. What leaks is the light
    // of VPLs near the cube's edges, whose cells have their centres outside (5.8% of the
    // injected energy at 24 cells): it falls as the cells shrink.
    let sealed = LpvSettings {
        blocking_lobe: BlockingLobe::Visibility,
        first_step_unblocked: false,
        inject_offset: 1.0,
        ..LpvSettings::default()
    };
    let watertight = leaks(&sealed, &[32, 24]);
    // VPLs moved toward their light instead land inside the cube wherever its edges fall.
    let toward = LpvSettings {
        inject_toward: vkgi::gi::lpv::InjectToward::Light,
        ..sealed.clone()
    };
    let toward_leaks = leaks(&toward, &[24]);
    // The default leaks through the partly covered cells at the cube's edges and in the first,
    // unblocked step, 8% still at 40 cells (7.2 across the cube).
    let default = leaks(&LpvSettings::default(), &[24, 16, 10]);
    eprintln!(
        "light sealed in a 100 mm cube, leak over the open light's indirect light per lattice: visibility {watertight:.4?}, toward the light {toward_leaks:.5?}, default {default:.4?}"
    );
    // 32 cells put 5.7 across the cube.
    assert!(watertight[0].1 <= 0.02, "{watertight:?}");
    assert!(falls_with_refinement(&watertight), "{watertight:?}");
    assert!(falls_with_refinement(&default), "{default:?}");
    assert!(toward_leaks[0].1 <= 1e-3, "{toward_leaks:?}");
    // Along the normal, the leak depends on where the cube's edges fall in the cells (1.3% to
    // 9% at 5.7 cells across for these three places, docs/lpv.md); toward the light it is gone
    // at each. Each place keeps its neighbours more than a cell from the cube: closer, their
    // lookups interpolate cells inside it.
    for centre in [
        Vec3::new(0.16, 0.35, 0.14),
        Vec3::new(0.40, 0.20, 0.12),
        Vec3::new(0.28, 0.40, 0.10),
    ] {
        let cube = (centre - 0.08, centre + 0.08);
        let leak = sealed_light_leaks(&gpu, &cornell, centre, cube, centre, &[20], &toward);
        eprintln!("a 160 mm cube at {centre}, toward the light: {leak:.5?}");
        assert!(leak[0].1 <= 1e-3, "{centre}: {leak:?}");
    }
    // The 0.5 m gap between the two rooms' walls (8.5 m across: 68 cells of 0.125 m put 4 across
    // it), closed around a light by a box that fills it; open, the light hangs in room A. The
    // default leaks 10% here (docs/lpv.md).
    let rooms = Scene::load("two-rooms").unwrap();
    let gap = Vec3::new(4.25, 1.5, 2.0);
    let filling = (Vec3::new(4.0, 0.0, 0.0), Vec3::new(4.5, 3.0, 4.0));
    let open = Vec3::new(2.0, 1.5, 2.0);
    let gap_leak = sealed_light_leaks(&gpu, &rooms, gap, filling, open, &[68], &sealed);
    eprintln!("light in the gap between the two rooms, visibility: {gap_leak:.4?}");
    assert!(gap_leak[0].1 <= 0.02, "{gap_leak:?}");
    common::assert_no_validation_errors(&gpu);
}

/// The Cornell box lit by a 10 W point light at `light` only, with a closed white cube of side
/// `side` centred on the light at offset zero that moves by `keys` (a dynamic object, the
/// mesh's last 12 triangles).
fn cornell_with_moving_cube(light: Vec3, side: f32, keys: Vec<(u64, Vec3)>) -> Scene {
    let cornell = Scene::load("cornell").unwrap();
    let half = Vec3::splat(0.5 * side);
    let mut scene = with_point_light(&cornell, light, 10.0, Some((light - half, light + half)));
    let n = scene.mesh.triangle_count();
    let cube: Vec<usize> = (n - 12..n).collect();
    let path = vkgi::scene::dynamic::Path::new(keys, false).unwrap();
    scene.add_dynamic("cube", &cube, path).unwrap();
    scene
}

/// Which pixels of a w x h view from `scene`'s camera see the scene but not its last 12
/// triangles (the cube).
fn outside_the_cube(scene: &Scene, (w, h): (u32, u32)) -> Vec<bool> {
    let cube_from = scene.mesh.triangle_count() - 12;
    (0..w * h)
        .map(|i| {
            let pixel = glam::Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let dir = scene.camera.ray_direction(pixel, w, h);
            scene
                .mesh
                .intersect(scene.camera.position, dir, 1e-4, 1e9)
                .is_some_and(|hit| hit.triangle < cube_from)
        })
        .collect()
}

/// The mean of the pixels `mask` keeps.
fn masked_mean(image: &[[f32; 3]], mask: &[bool]) -> f64 {
    let kept: Vec<[f32; 3]> = image
        .iter()
        .zip(mask)
        .filter(|(_, keep)| **keep)
        .map(|(p, _)| *p)
        .collect();
    common::mean(&kept)
}

/// Run `scene`'s animation for `frames` frames with one lattice of `settings`, which must follow
/// every move, and return the last frame's indirect light.
fn animate(
    gpu: &vkgi::gpu::Gpu,
    scene: &mut Scene,
    settings: &LpvSettings,
    size: (u32, u32),
    frames: u32,
) -> Vec<[f32; 3]> {
    let options = common::indirect_only(size.0, size.1);
    let mut frame = vkgi::render::Frame::new(gpu, scene, options).unwrap();
    let lpv = Lpv::new(&Setup::new(gpu, scene), settings.clone()).unwrap();
    let mut method: Box<dyn vkgi::gi::GiMethod> = Box::new(lpv);
    let rebuild = |_: &Scene| -> anyhow::Result<Box<dyn vkgi::gi::GiMethod>> {
        anyhow::bail!("LPV follows moved geometry: it is never built again")
    };
    let ring = vkgi::render::runner::run_animation(
        gpu,
        &mut frame,
        scene,
        Some(&mut method),
        &rebuild,
        frames,
    )
    .unwrap();
    drop(ring);
    frame.read_hdr(gpu).unwrap()
}

#[test]
fn the_gpu_geometry_lattices_follow_a_moved_block_exactly() {
    use vkgi::gi::{Follow, GiMethod};
    use vkgi::scene::dynamic::Moved;
    let gpu = common::gpu();
    let light = Vec3::new(0.16, 0.35, 0.14);
    let away = Vec3::new(0.24, 0.09, 0.26);
    let mut scene = cornell_with_moving_cube(light, 0.2, vec![(0, Vec3::ZERO), (1, away)]);
    // The rebuilt cells go up as runs of the buffers' order: rows along x, columns along z.
    for (lobe, order) in [
        (BlockingLobe::TwoSided, CellOrder::Rows),
        (BlockingLobe::TwoSided, CellOrder::Columns),
        (BlockingLobe::Projected, CellOrder::Rows),
        (BlockingLobe::Oriented, CellOrder::Columns),
        (BlockingLobe::Visibility, CellOrder::Rows),
        (BlockingLobe::Visibility, CellOrder::Columns),
    ] {
        scene.pose(0);
        let settings = LpvSettings {
            lattice: 16,
            rsm: 32,
            blocking_lobe: lobe,
            cell_order: Some(order),
            lookup_filter: Some(LookupFilter::Texels),
            ..LpvSettings::default()
        };
        let options = common::indirect_only(16, 12);
        let mut frame = vkgi::render::Frame::new(&gpu, &scene, options).unwrap();
        let setup = Setup::new(&gpu, &scene);
        let mut method = two_scale::TwoScale::new(&setup, settings.clone(), 5).unwrap();
        assert_eq!(
            [method.near.cell_order(), method.far.cell_order()],
            [order; 2]
        );
        let mut ring = vkgi::gpu::frames::FrameRing::new(&gpu, 2).unwrap();
        frame.submit(&gpu, &mut ring, Some(&mut method)).unwrap();
        // Move the cube while the first frame may still be in flight.
        let moved = scene.pose(1);
        for m in &moved {
            frame.set_vertices(&scene, m.vertices.clone());
        }
        let follow = method.geometry_moved(&gpu, &scene, &Moved::regions(&moved));
        assert_eq!(follow.unwrap(), Follow::Followed);
        frame.submit(&gpu, &mut ring, Some(&mut method)).unwrap();
        ring.finish().unwrap();
        // The same lattices built afresh for the moved scene.
        let fresh = two_scale::TwoScale::new(&Setup::new(&gpu, &scene), settings, 5).unwrap();
        for (followed, built, field) in [
            (&method.near, &fresh.near, "near"),
            (&method.far, &fresh.far, "far"),
        ] {
            let update = followed.geometry_update().unwrap();
            eprintln!("{lobe:?} {order:?}, {field} field: {update:?}");
            assert_eq!(
                followed.read_geometry(&gpu).unwrap(),
                built.read_geometry(&gpu).unwrap(),
                "{lobe:?} {order:?}, {field} field"
            );
            if lobe == BlockingLobe::Oriented {
                assert_eq!(update.rebuilt, update.cells);
            } else {
                assert!(update.rebuilt < update.cells, "{update:?}");
            }
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_cube_moved_onto_a_light_seals_it_and_moved_off_frees_it_within_one_over_one_minus_lambda_frames()
 {
    let gpu = common::gpu();
    // A 0.16 m cube around a point light above the short block (20 cells of 28 mm put 5.7
    // across it), and the cube's place away from the light, above the tall block. Visibility
    // blocking, leak-tight settings: placed around the light, the cube leaks nothing.
    let light = Vec3::new(0.16, 0.35, 0.14);
    let away = Vec3::new(0.24, 0.09, 0.26);
    let (side, size) = (0.16, (32, 24));
    let cornell = Scene::load("cornell").unwrap();
    let open = with_point_light(&cornell, light, 10.0, None);
    let half = Vec3::splat(0.5 * side);
    let placed = |at: Vec3| with_point_light(&cornell, light, 10.0, Some((at - half, at + half)));
    for lambda in [0.5f32, 0.9] {
        let settings = LpvSettings {
            lattice: 20,
            rsm: 64,
            incremental: lambda,
            blocking_lobe: BlockingLobe::Visibility,
            first_step_unblocked: false,
            inject_offset: 1.0,
            inject_toward: vkgi::gi::lpv::InjectToward::Light,
            ..LpvSettings::default()
        };
        let settle = vkgi::gi::lpv::entry::settle_frames(f64::from(lambda));
        let after = (1.0 / (1.0 - f64::from(lambda))).ceil() as u32;
        let still = |scene: &Scene| {
            let options = common::indirect_only(size.0, size.1);
            common::render_gi(&gpu, scene, settings.clone(), options, settle)
        };
        let jump = |from: Vec3, to: Vec3| {
            let keys = vec![
                (0, from),
                (u64::from(settle), from),
                (u64::from(settle) + 1, to),
            ];
            let mut scene = cornell_with_moving_cube(light, side, keys);
            let image = animate(&gpu, &mut scene, &settings, size, settle + 1 + after);
            (image, outside_the_cube(&scene, size))
        };
        // The cube settles away from the light, then jumps around it: the light outside is
        // that of the cube placed there from the start, and what is left of the open light's.
        let (closed, mask) = jump(away, Vec3::ZERO);
        let open_mean = masked_mean(&still(&open), &mask);
        let leak = masked_mean(&closed, &mask) / open_mean;
        let placed_leak = masked_mean(&still(&placed(light)), &mask) / open_mean;
        // And back: the cube settles around the light, then jumps away.
        let (opened, mask) = jump(Vec3::ZERO, away);
        let placed_away = masked_mean(&still(&placed(light + away)), &mask);
        let freed = masked_mean(&opened, &mask) / placed_away;
        eprintln!(
            "λ {lambda}, {after} frames after the move: the cube moved onto the light leaks {leak:.5} of the open light (placed there: {placed_leak:.5}); moved off, the light outside is {freed:.5} of the cube placed away"
        );
        // The blend alone keeps λ^n of the light from before the move after n frames; the
        // steps of each frame remove most of the rest (the light reaching the walls): at most
        // a quarter of that is left either way.
        let kept = f64::from(lambda).powi(after as i32) / 4.0;
        assert!(
            leak - placed_leak <= kept,
            "λ {lambda}: {leak} against {placed_leak}"
        );
        assert!(1.0 - freed <= kept, "λ {lambda}: {freed}");
        assert!(placed_leak <= 1e-3, "{placed_leak}");
        if lambda >= 0.9 {
            assert!(leak <= 0.02, "λ {lambda}: {leak}");
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn ilpv_bleeds_the_wall_colours_onto_the_blocks_and_floor() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (w, h) = (96, 72);
    let image = common::render_gi(
        &gpu,
        &scene,
        LpvSettings::default(),
        common::indirect_only(w, h),
        16,
    );
    // Classify pixels by what they see: white surfaces facing the red wall (+x) or the green
    // wall (-x), and the floor next to each wall.
    let (mut toward_red, mut toward_green) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let dir =
                scene
                    .camera
                    .ray_direction(glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5), w, h);
            let Some(hit) = scene.mesh.intersect(scene.camera.position, dir, 1e-4, 1e9) else {
                continue;
            };
            let material = &scene.materials[scene.mesh.materials[hit.triangle] as usize];
            if material.name != "white" {
                continue;
            }
            let p = scene.camera.position + dir * hit.t;
            let n = scene.mesh.face_normal(hit.triangle);
            let c = image[(y * w + x) as usize];
            let floor = n.y.abs() > 0.99 && p.y < 1e-3;
            if (n.x.abs() > 0.9 && n.x * (p.x - 0.28) > 0.0 && p.y > 0.02) || (floor && p.x > 0.45)
            {
                toward_red.push(c);
            }
            if (n.x.abs() > 0.9 && n.x * (p.x - 0.28) < 0.0 && p.y > 0.02) || (floor && p.x < 0.1) {
                toward_green.push(c);
            }
        }
    }
    let sum = |v: &[[f32; 3]]| {
        v.iter().fold([0.0f64; 3], |a, p| {
            [
                a[0] + f64::from(p[0]),
                a[1] + f64::from(p[1]),
                a[2] + f64::from(p[2]),
            ]
        })
    };
    let (r, g) = (sum(&toward_red), sum(&toward_green));
    eprintln!(
        "{} pixels toward red: {r:?}; {} toward green: {g:?}",
        toward_red.len(),
        toward_green.len()
    );
    assert!(toward_red.len() > 20 && toward_green.len() > 20);
    assert!(
        r[0] > 1.3 * r[1],
        "white surfaces facing the red wall get red light: {r:?}"
    );
    assert!(
        g[1] > 1.3 * g[0],
        "white surfaces facing the green wall get green light: {g:?}"
    );
    common::assert_no_validation_errors(&gpu);
}

/// The lattice energy (all channels) ILPV reads after the last frame, and the frames' images.
fn run_ilpv_frames(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    settings: LpvSettings,
    frames: u32,
) -> (Lpv, Vec<f64>) {
    let mut frame = vkgi::render::Frame::new(gpu, scene, common::indirect_only(16, 12)).unwrap();
    let mut lpv = Lpv::new(&Setup::new(gpu, scene), settings).unwrap();
    let mut ring = vkgi::gpu::frames::FrameRing::new(gpu, 2).unwrap();
    let mut energies = Vec::new();
    for f in 1..=frames {
        frame.submit(gpu, &mut ring, Some(&mut lpv)).unwrap();
        if f % 100 == 0 || f == frames {
            ring.finish().unwrap();
            let lattices = lpv.read_result(gpu).unwrap();
            for l in &lattices {
                assert!(
                    l.iter().flatten().all(|v| v.is_finite()),
                    "non-finite lattice at frame {f}"
                );
            }
            energies.push(lattices.iter().map(|l| energy(l)).sum());
        }
    }
    ring.finish().unwrap();
    (lpv, energies)
}

#[test]
fn ilpv_blends_incrementally_in_a_scene_lit_by_an_area_light_alone() {
    // The energy ratio of eq 3.4 counted punctual lights only: with an area light alone the
    // energy was 0 and ILPV fell back to plain propagation every frame (found by the report
    // giving identical images at λ 0.5 and 0.9 on cornell-area).
    let gpu = common::gpu();
    let scene = Scene::load("cornell-area").unwrap();
    let settings = LpvSettings {
        incremental: 0.7,
        rsm: 32,
        ..ilpv(8)
    };
    let (lpv, _) = run_ilpv_frames(&gpu, &scene, settings, 2);
    let (a, b) = lpv.blend_weights(0);
    assert!(
        (a - 0.7).abs() < 1e-6 && (b - 0.3).abs() < 1e-6,
        "blend weights ({a}, {b})"
    );
    common::assert_no_validation_errors(&gpu);
}

/// The mean indirect luminance of each of `frames` frames of `scene` under ILPV (in two scales
/// where `settings` ask for them).
fn indirect_means_per_frame(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    settings: LpvSettings,
    frames: u32,
) -> Vec<f64> {
    let mut frame = vkgi::render::Frame::new(gpu, scene, common::indirect_only(32, 24)).unwrap();
    let mut method = two_scale::create(&Setup::new(gpu, scene), settings).unwrap();
    let mut ring = vkgi::gpu::frames::FrameRing::new(gpu, 2).unwrap();
    (0..frames)
        .map(|_| {
            frame.submit(gpu, &mut ring, Some(method.as_mut())).unwrap();
            ring.finish().unwrap();
            common::mean(&frame.read_hdr(gpu).unwrap())
        })
        .collect()
}

#[test]
fn no_frame_flashes_above_the_settled_indirect_light() {
    // The first frame used to inject at full weight and frame 2 carried all of it on at λ: at
    // λ 0.99 frame 2 was 4x the settled light on this scene (10.8x at lattice 10), at 0.999 32x.
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    // One lattice, and two scales (a 5-cell far field under a 10-cell near field).
    for (lambda, far_lattice) in [0.5f32, 0.9, 0.99, 0.999]
        .into_iter()
        .flat_map(|l| [(l, FarLattice::Off), (l, FarLattice::Cells(5))])
    {
        let settings = LpvSettings {
            incremental: lambda,
            rsm: 64,
            far_lattice,
            ..LpvSettings::default()
        };
        let means = indirect_means_per_frame(&gpu, &scene, settings, 40);
        let settled = means[means.len() - 1];
        let highest = means.iter().cloned().fold(0.0, f64::max);
        eprintln!(
            "λ {lambda} far {far_lattice:?}: frames 1-4 {:.5?}, settled {settled:.5}, highest / settled {:.4}",
            &means[..4],
            highest / settled
        );
        assert!(
            (means[means.len() - 2] - settled).abs() < 1e-3 * settled,
            "not settled at λ {lambda}: {means:?}"
        );
        assert!(
            highest <= 1.05 * settled,
            "λ {lambda}: a frame reaches {highest} against the settled {settled}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// The mean of each colour channel of an image.
fn channel_means(pixels: &[[f32; 3]]) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for p in pixels {
        for c in 0..3 {
            sum[c] += f64::from(p[c]);
        }
    }
    sum.map(|s| s / pixels.len() as f64)
}

/// How the lights of a frame sequence change.
#[derive(Clone, Copy, Debug)]
enum LightsEachFrame {
    /// Set once, then left as they are.
    Stay,
    /// Handed to the frame again, unchanged, before every frame (which counts as a change).
    SetAgain,
    /// `FrameOptions::lights_move`: treated as moved in every frame.
    Move,
}

/// A frame whose lights and geometry did not change copies the kept injection instead of
/// rendering the RSM and injecting again: the same bits (fixed-point injection) as frames that
/// inject anew every time, for ILPV's two scales and for LPV; the RSM is rendered in the first
/// frame only. Frames whose lights move in every frame (`lights_move`) inject anew and keep
/// nothing: no copy either way.
#[test]
fn a_frame_whose_lights_and_geometry_stayed_reuses_the_kept_injection_with_the_same_bits() {
    use vkgi::gi::lpv::Injection;
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        let settings = LpvSettings {
            scheme,
            injection: Injection::Fixed,
            rsm: 64,
            ..LpvSettings::default()
        };
        let run = |lights: LightsEachFrame| {
            let options = vkgi::render::FrameOptions {
                lights_move: matches!(lights, LightsEachFrame::Move),
                ..common::indirect_only(32, 24)
            };
            let mut frame = vkgi::render::Frame::new(&gpu, &scene, options).unwrap();
            let mut method =
                two_scale::create(&Setup::new(&gpu, &scene), settings.clone()).unwrap();
            let mut ring = vkgi::gpu::frames::FrameRing::new(&gpu, 2).unwrap();
            for _ in 0..4 {
                if matches!(lights, LightsEachFrame::SetAgain) {
                    frame.set_lights(&scene);
                }
                frame
                    .submit(&gpu, &mut ring, Some(method.as_mut()))
                    .unwrap();
            }
            ring.finish().unwrap();
            let report = ring.profiler.report();
            let runs = |name: &str| {
                report
                    .passes
                    .iter()
                    .filter(|p| p.name.starts_with(name))
                    .map(|p| p.per_frame_ns.len())
                    .max()
                    .unwrap_or(0)
            };
            let passes = [runs("rsm"), runs("kept injection"), runs("keep injection")];
            (frame.read_hdr(&gpu).unwrap(), passes)
        };
        let (kept, kept_passes) = run(LightsEachFrame::Stay);
        assert!(
            kept.iter().flatten().any(|&v| v > 0.0),
            "{scheme:?}: no indirect light"
        );
        // Frames with an RSM, copies of the kept injection, copies into it.
        for (lights, passes) in [
            (LightsEachFrame::Stay, [1, 3, 1]),
            (LightsEachFrame::SetAgain, [4, 0, 4]),
            (LightsEachFrame::Move, [4, 0, 0]),
        ] {
            let (image, counted) = match lights {
                LightsEachFrame::Stay => (kept.clone(), kept_passes),
                _ => run(lights),
            };
            assert_eq!(kept, image, "{scheme:?}, {lights:?}: not the same image");
            assert_eq!(
                counted, passes,
                "{scheme:?}, {lights:?}: RSM frames and copies"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn ilpv_follows_a_dimmed_or_recoloured_light_from_the_next_frame() {
    // Eq 3.4 scales the carried light by E_now / E_before (per colour channel here), so a light
    // dimmed to half, or tinted, changes the indirect light in proportion at once; the blend
    // alone would take about 1/(1-λ) = 10 frames to forget the old light.
    let gpu = common::gpu();
    let mut scene = Scene::load("cornell").unwrap();
    let settings = LpvSettings {
        incremental: 0.9,
        rsm: 64,
        ..LpvSettings::default()
    };
    let mut frame = vkgi::render::Frame::new(&gpu, &scene, common::indirect_only(32, 24)).unwrap();
    let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), settings).unwrap();
    let mut ring = vkgi::gpu::frames::FrameRing::new(&gpu, 2).unwrap();
    let mut render = |frame: &mut vkgi::render::Frame, lpv: &mut Lpv| {
        frame.submit(&gpu, &mut ring, Some(lpv)).unwrap();
        ring.finish().unwrap();
        channel_means(&frame.read_hdr(&gpu).unwrap())
    };
    let mut settled = [0.0; 3];
    for _ in 0..60 {
        settled = render(&mut frame, &mut lpv);
    }
    scene.lights[0].flux *= 0.5;
    frame.set_lights(&scene);
    let dimmed = render(&mut frame, &mut lpv);
    let ratios: Vec<f64> = (0..3).map(|c| dimmed[c] / settled[c]).collect();
    scene.lights[0].color = glam::Vec3::new(1.0, 0.2, 0.2);
    frame.set_lights(&scene);
    let tinted = render(&mut frame, &mut lpv);
    let tint_ratios: Vec<f64> = (0..3).map(|c| tinted[c] / dimmed[c]).collect();
    eprintln!(
        "indirect light the frame after: dimmed to half {ratios:.5?}, tinted (1, 0.2, 0.2) {tint_ratios:.5?}"
    );
    for c in 0..3 {
        assert!((ratios[c] - 0.5).abs() < 1e-3, "{ratios:?}");
        let expected = [1.0, 0.2, 0.2][c];
        assert!((tint_ratios[c] - expected).abs() < 1e-3, "{tint_ratios:?}");
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn ilpv_reaches_the_closed_form_steady_state() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (lambda, steps) = (0.8f64, 8usize);
    let settings = LpvSettings {
        lattice: 12,
        iterations: steps as u32,
        incremental: lambda as f32,
        rsm: 64,
        ilpv_lookup: IlpvLookup::Final,
        ..LpvSettings::default()
    };
    // The injected lattice I: one frame without propagation or blending.
    let injected_settings = LpvSettings {
        iterations: 0,
        incremental: 0.0,
        ..settings.clone()
    };
    let (injector, _) = run_ilpv_frames(&gpu, &scene, injected_settings, 1);
    let injected = injector.read_result(&gpu).unwrap();
    let (lpv, _) = run_ilpv_frames(&gpu, &scene, settings, 100);
    let steady = lpv.read_result(&gpu).unwrap();
    // Closed form (seed spec §14): L* = (1-λ) Σ_k λ^k F^(k+1)(I), F = one frame's N steps.
    let geometry = vkgi::gi::lpv::geometry::build(
        &scene.mesh,
        &lpv.lattice,
        &lpv.transfer,
        lpv.settings.blocking_lobe,
    );
    let frame_steps = |mut l: Vec<DVec4>| {
        for step in 0..steps {
            cpu::compensate_clamp(&mut l, &lpv.transfer, 0.0, 0.0);
            let p = StepParams {
                absorption: 0.0,
                scattering: 0.0,
                use_blocking: step > 0,
            };
            l = cpu::step_26(&lpv.lattice, &l, &geometry, &lpv.transfer, p);
        }
        l
    };
    let (mut worst, mut worst_fixed_point) = (0.0f64, 0.0f64);
    for c in 0..3 {
        let as_f64 = |l: &[[f32; 4]]| -> Vec<DVec4> {
            l.iter().map(|v| DVec4::from(v.map(f64::from))).collect()
        };
        // The GPU state is a fixed point of the recursion L = F((1-λ) I + λ L).
        let mut mixed = as_f64(&injected[c]);
        for (m, s) in mixed.iter_mut().zip(as_f64(&steady[c])) {
            *m = *m * (1.0 - lambda) + s * lambda;
        }
        worst_fixed_point = worst_fixed_point.max(relative_error(&steady[c], &frame_steps(mixed)));
        let mut term = as_f64(&injected[c]);
        let mut closed = vec![DVec4::ZERO; term.len()];
        let mut weight = 1.0 - lambda;
        while weight > 1e-9 {
            term = frame_steps(term);
            for (a, t) in closed.iter_mut().zip(&term) {
                *a += *t * weight;
            }
            weight *= lambda;
        }
        let error = relative_error(&steady[c], &closed);
        worst = worst.max(error);
    }
    eprintln!(
        "ILPV steady state: fixed point of the recursion to {worst_fixed_point:e}, closed form to {worst:e}"
    );
    assert!(worst_fixed_point < 1e-4, "{worst_fixed_point}");
    // The closed form is linear; the clamp and the clamp compensation make one frame's steps
    // slightly nonlinear (F(a + b) != F(a) + F(b) where the clamp cuts differently): measured
    // 1.5e-3 on this scene.
    assert!(worst < 3e-3, "{worst}");
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn ilpv_with_lambda_099_stays_bounded_for_1000_frames() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    // One step per frame, and it is the unblocked first step: light only leaves through the
    // lattice's border, the feedback carries 99% of it on, with and without clamp compensation.
    for clamp_compensation in [true, false] {
        let settings = LpvSettings {
            lattice: 8,
            iterations: 1,
            incremental: 0.99,
            rsm: 16,
            ilpv_lookup: IlpvLookup::Final,
            clamp_compensation,
            ..LpvSettings::default()
        };
        let (_, energies) = run_ilpv_frames(&gpu, &scene, settings.clone(), 1000);
        let injected_settings = LpvSettings {
            iterations: 0,
            incremental: 0.0,
            ..settings
        };
        let (injector, _) = run_ilpv_frames(&gpu, &scene, injected_settings, 1);
        let injected: f64 = injector
            .read_result(&gpu)
            .unwrap()
            .iter()
            .map(|l| energy(l))
            .sum();
        eprintln!(
            "compensation {clamp_compensation}: energy every 100 frames (injected {injected:.4}): {energies:.4?}"
        );
        // The blend's fixed point holds at most the injected energy, plus the clamp's gain on
        // the fresh 1% of light each frame when uncompensated.
        let bound = if clamp_compensation { 1.0 + 1e-3 } else { 1.05 };
        assert!(
            energies.iter().all(|&e| e > 0.0 && e <= injected * bound),
            "{energies:?}"
        );
        let last = energies[energies.len() - 1];
        assert!(
            (last - energies[energies.len() - 2]).abs() < 1e-2 * last,
            "not settled: {energies:?}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// Every pixel finite and below `bound`.
fn assert_finite_and_bounded(image: &[[f32; 3]], bound: f32, what: &str) {
    for p in image {
        assert!(
            p.iter().all(|v| v.is_finite() && *v >= 0.0 && *v <= bound),
            "{what}: pixel {p:?}"
        );
    }
}

#[test]
fn hard_cases_stay_finite_and_bounded() {
    let gpu = common::gpu();
    let cornell = Scene::load("cornell").unwrap();
    let options = || common::indirect_only(32, 24);
    let reference = common::render_gi(&gpu, &cornell, ilpv(12), options(), 4);
    let bound = 100.0 * reference.iter().flatten().fold(0.0f32, |a, v| a.max(*v));
    // Flux 1e6 and 1e-6: the same image, scaled.
    let scaled = |flux: f32| {
        let mut scene = cornell.clone();
        scene.lights[0].flux = flux;
        common::render_gi(&gpu, &scene, ilpv(12), options(), 4)
    };
    let (high, low) = (scaled(1e6), scaled(1e-6));
    for ((h, l), r) in high.iter().zip(&low).zip(&reference) {
        for c in 0..3 {
            let (h, l) = (f64::from(h[c]) / 1e6, f64::from(l[c]) / 1e-6);
            assert!(h.is_finite() && l.is_finite());
            assert!(
                (h - l).abs() <= 1e-4 * h.abs().max(1e-6 * f64::from(bound)),
                "{h} vs {l} (1-W image {})",
                r[c]
            );
        }
    }
    // Zero flux: exactly no light.
    let dark = scaled(0.0);
    assert!(
        dark.iter().flatten().all(|&v| v == 0.0),
        "zero flux must give zero light"
    );
    // 512 steps; lattices of 1 and 2 cells.
    for (lattice, iterations) in [(8, 512), (1, 8), (2, 8)] {
        let settings = LpvSettings {
            lattice,
            iterations,
            ..LpvSettings::default()
        };
        let image = common::render_gi(&gpu, &cornell, settings, options(), 2);
        assert_finite_and_bounded(
            &image,
            bound,
            &format!("lattice {lattice}, {iterations} steps"),
        );
    }
    // A scene with a zero-thickness axis gets a flat lattice.
    let plane = common::plane_under_point_light(0.6, 50.0);
    let flat = Lpv::new(&Setup::new(&gpu, &plane), ilpv(16)).unwrap();
    assert_eq!(flat.lattice.dims.y, 1);
    let image = common::render_gi(&gpu, &plane, ilpv(16), options(), 4);
    assert_finite_and_bounded(&image, f32::MAX, "flat scene");
    // A light inside the wall between the two rooms.
    let mut rooms = Scene::load("two-rooms").unwrap();
    rooms.lights[0].position = Vec3::new(4.25, 1.5, 2.0);
    let image = common::render_gi(&gpu, &rooms, ilpv(16), options(), 4);
    assert_finite_and_bounded(&image, f32::MAX, "light inside a wall");
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn two_scales_over_one_lattice_partition_its_steps() {
    // A "far field" on the near field's own lattice under a near field of one step (its
    // injection alone) is one lattice cut after its first step: with α = 0 the two
    // accumulations add up to the one lattice's, with α = 1 to it plus the injection (λ 0, 6
    // steps). Compared on the lattices: each lookup clamps its own negative lobes.
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let setup = Setup::new(&gpu, &scene);
    let one = LpvSettings {
        incremental: 0.0,
        iterations: 6,
        rsm: 64,
        far_lattice: FarLattice::Off,
        ..ilpv(8)
    };
    let options = || common::indirect_only(16, 12);
    let mut single = Lpv::new(&setup, one.clone()).unwrap();
    common::render_with(&gpu, &scene, &mut single, options(), 4);
    let whole = single.read_result(&gpu).unwrap();
    let mut injection = Lpv::new(
        &setup,
        LpvSettings {
            iterations: 1,
            ..one.clone()
        },
    )
    .unwrap();
    common::render_with(&gpu, &scene, &mut injection, options(), 4);
    let m0 = injection.read_result(&gpu).unwrap();
    for far_injection in [0.0f32, 1.0] {
        let settings = LpvSettings {
            near_steps: 1,
            far_injection,
            ..one.clone()
        };
        let mut two = two_scale::TwoScale::new(&setup, settings, 8).unwrap();
        common::render_with(&gpu, &scene, &mut two, options(), 4);
        let near = two.near.read_result(&gpu).unwrap();
        let far = two.far.read_result(&gpu).unwrap();
        let (mut worst, mut largest) = (0.0f64, 0.0f64);
        for c in 0..3 {
            for i in 0..whole[c].len() {
                for k in 0..4 {
                    let expected = f64::from(whole[c][i][k])
                        + f64::from(far_injection) * f64::from(m0[c][i][k]);
                    let got = f64::from(near[c][i][k]) + f64::from(far[c][i][k]);
                    worst = worst.max((got - expected).abs());
                    largest = largest.max(expected.abs());
                }
            }
        }
        assert!(largest > 0.0);
        assert!(
            worst <= 1e-5 * largest,
            "α {far_injection}: largest difference {worst} against the largest value {largest}"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// Indirect light of the default ILPV and of LPV on the Cornell box against the path tracer's
/// indirect part (bounces 1: exactly the one bounce LPV models), beside the registered ambient
/// baseline fitted to the same reference (albedo times the per-channel irradiance that
/// minimises the squared error).
#[test]
fn default_settings_beat_the_best_constant_ambient_term() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let (w, h) = (64, 48);
    let settings = vkgi::reference::ReferenceSettings {
        width: w,
        height: h,
        spp: 256,
        bounces: vkgi::reference::Bounces::Limited(1),
        seed: 1,
        strategy: Default::default(),
    };
    let mut tracer = vkgi::reference::PathTracer::new(&gpu, &scene, w, h).unwrap();
    let reference = tracer.render(&gpu, &settings, |_, _| {}).unwrap();
    let truth = reference.indirect.clone();
    let score = |pixels: Vec<[f32; 3]>| {
        vkgi::metrics::compare(&vkgi::imageio::HdrImage::new(w, h, pixels), &truth, None).unwrap()
    };
    let baseline = vkgi::gi::registry::find("ambient").expect("the ambient baseline");
    let setup = Setup {
        reference: Some(&reference),
        ..Setup::new(&gpu, &scene)
    };
    let mut ambient = baseline
        .create(&setup, &baseline.settings(&[]).unwrap())
        .unwrap();
    let ambient_score = score(common::render_with(
        &gpu,
        &scene,
        ambient.as_mut(),
        common::indirect_only(w, h),
        1,
    ));
    let ilpv_at = |lattice: u32| {
        let settings = LpvSettings {
            lattice,
            ..LpvSettings::default()
        };
        let mut method = two_scale::create(&Setup::new(&gpu, &scene), settings).unwrap();
        score(common::render_with(
            &gpu,
            &scene,
            method.as_mut(),
            common::indirect_only(w, h),
            16,
        ))
    };
    let ilpv_score = ilpv_at(vkgi::gi::lpv::technique::DEFAULT_LATTICE);
    let finer: Vec<(u32, f64)> = [16, 32].map(|l| (l, ilpv_at(l).rel_mse)).to_vec();
    let lpv_settings = LpvSettings {
        scheme: Scheme::Lpv,
        iterations: 32,
        ..LpvSettings::default()
    };
    let lpv_score = score(common::render_gi(
        &gpu,
        &scene,
        lpv_settings,
        common::indirect_only(w, h),
        1,
    ));
    for (name, s) in [
        ("ambient", &ambient_score),
        ("ilpv default", &ilpv_score),
        ("lpv 32 steps", &lpv_score),
    ] {
        eprintln!(
            "{name:>13}: RMSE {:.5} relMSE {:.5} FLIP {:.4}",
            s.rmse, s.rel_mse, s.flip
        );
    }
    eprintln!("ilpv (two scales) relMSE at lattices 16, 32: {finer:.5?}");
    // Issue #12 item 4: error that does not rise from 10³ to 32³, and ILPV's best under a
    // third of the best constant ambient term's.
    let at_32 = finer[1].1;
    assert!(
        at_32 <= ilpv_score.rel_mse,
        "relMSE {at_32} at 32³ against {} at 10³",
        ilpv_score.rel_mse
    );
    let best = finer.iter().map(|f| f.1).fold(ilpv_score.rel_mse, f64::min);
    assert!(
        best <= ambient_score.rel_mse / 3.0,
        "best ILPV relMSE {best} against ambient {}",
        ambient_score.rel_mse
    );
    assert!(
        ilpv_score.rmse < ambient_score.rmse,
        "ILPV {ilpv_score:?} vs ambient {ambient_score:?}"
    );
    assert!(
        ilpv_score.rel_mse < ambient_score.rel_mse,
        "ILPV {ilpv_score:?} vs ambient {ambient_score:?}"
    );
    assert!(
        ilpv_score.flip < ambient_score.flip,
        "ILPV {ilpv_score:?} vs ambient {ambient_score:?}"
    );
    common::assert_no_validation_errors(&gpu);
}

/// A half float's value.
fn half(bits: u16) -> f64 {
    let sign = if bits >> 15 == 1 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f64::from(bits & 0x3ff);
    match exponent {
        0 => sign * mantissa * 2f64.powi(-24),
        31 => f64::NAN,
        _ => sign * (1.0 + mantissa / 1024.0) * 2f64.powi(exponent - 15),
    }
}

/// A view's image of four floats per texel (`half`: 16-bit ones) as f64 vectors.
fn texels(gpu: &vkgi::gpu::Gpu, image: &vkgi::gpu::Image, half_floats: bool) -> Vec<DVec4> {
    let bytes = gpu.read_image(image).unwrap();
    if half_floats {
        let words: &[u16] = bytemuck::cast_slice(&bytes);
        words
            .chunks(4)
            .map(|t| DVec4::new(half(t[0]), half(t[1]), half(t[2]), half(t[3])))
            .collect()
    } else {
        let words: &[f32] = bytemuck::cast_slice(&bytes);
        words
            .chunks(4)
            .map(|t| DVec4::new(t[0].into(), t[1].into(), t[2].into(), t[3].into()))
            .collect()
    }
}

/// The lookup in f64: at `p` pushed `offset` cells along `n`, the lattices' trilinear
/// interpolation (cells outside count as empty) projected on SH_cos(-n), clamped at zero and
/// scaled, per channel.
fn cpu_lookup(lpv: &Lpv, lattices: &[Vec<[f32; 4]>; 3], p: DVec3, n: DVec3) -> DVec3 {
    let field = lpv.lookup_field();
    let cell = f64::from(field.cell_size);
    let dims = [field.dims[0], field.dims[1], field.dims[2]];
    let at = p + n * (f64::from(field.offset) * cell);
    let u = (at - field.origin.as_dvec3()) / cell - DVec3::splat(0.5);
    let base = u.floor();
    let f = u - base;
    let lobe = sh::cosine_lobe(-n);
    let mut incident = DVec3::ZERO;
    for k in 0..8 {
        let corner = [k & 1, (k >> 1) & 1, (k >> 2) & 1];
        let c = [0, 1, 2].map(|a| base[a] as i32 + corner[a]);
        if (0..3).any(|a| c[a] < 0 || c[a] >= dims[a]) {
            continue;
        }
        let w: f64 = (0..3)
            .map(|a| if corner[a] == 1 { f[a] } else { 1.0 - f[a] })
            .product();
        let i = ((c[2] * dims[1] + c[1]) * dims[0] + c[0]) as usize;
        let sh = |channel: usize| DVec4::from_array(lattices[channel][i].map(f64::from));
        incident += w * DVec3::new(sh(0).dot(lobe), sh(1).dot(lobe), sh(2).dot(lobe));
    }
    incident.max(DVec3::ZERO) * f64::from(field.scale)
}

/// A frame's HDR image and the G-buffer's position, normal and albedo after `frames` frames.
struct Rendered {
    hdr: Vec<[f32; 3]>,
    position: Vec<DVec4>,
    normal: Vec<DVec4>,
    albedo: Vec<DVec4>,
}

fn render_indirect(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    method: &mut dyn vkgi::gi::GiMethod,
) -> Rendered {
    let mut frame = vkgi::render::Frame::new(gpu, scene, common::indirect_only(40, 30)).unwrap();
    drop(vkgi::render::runner::run_frames(gpu, &mut frame, Some(method), 0, 3).unwrap());
    let g = &frame.views[0].gbuffer;
    Rendered {
        hdr: frame.read_hdr(gpu).unwrap(),
        position: texels(gpu, &g.position, false),
        normal: texels(gpu, &g.normal, true),
        albedo: texels(gpu, &g.albedo, true),
    }
}

/// The GPU lookup of `fields` against the f64 lookup of their read-back lattices.
fn assert_lookup_matches(gpu: &vkgi::gpu::Gpu, name: &str, fields: &[&Lpv], r: &Rendered) {
    let lattices: Vec<[Vec<[f32; 4]>; 3]> =
        fields.iter().map(|l| l.read_result(gpu).unwrap()).collect();
    let (mut worst, mut brightest, mut difference, mut total) = (0.0f64, 0.0f64, 0.0, 0.0);
    for (i, gpu_pixel) in r.hdr.iter().enumerate() {
        let expected = if r.position[i].w == 0.0 {
            DVec3::ZERO
        } else {
            let n = r.normal[i].truncate().normalize();
            let p = r.position[i].truncate();
            let light: DVec3 = fields
                .iter()
                .zip(&lattices)
                .map(|(lpv, l)| cpu_lookup(lpv, l, p, n))
                .sum();
            r.albedo[i].truncate() * light
        };
        for c in 0..3 {
            let d = (f64::from(gpu_pixel[c]) - expected[c]).abs();
            worst = worst.max(d);
            brightest = brightest.max(expected[c]);
            difference += d;
            total += expected[c];
        }
    }
    assert!(total > 0.0, "{name}: no indirect light");
    assert!(
        worst <= 1e-4 * brightest && difference <= 1e-5 * total,
        "{name}: worst {worst} of {brightest}, summed {difference} of {total}"
    );
}

/// The lookup, reading the lattices each way (3-D copies the sampler filters, or the lattice
/// buffers as texels interpolated in the shader, each pixel fetching its own or the subgroup's
/// lanes fetching them together; the accumulation, and ILPV's final lattice,
/// one of a ping-pong pair), and two scales looking up both lattices in one pass: all against
/// the f64 lookup of the same lattices and G-buffer. lavapipe filters with
/// float weights; a GPU's sampler has its subTexelPrecisionBits (8 on most), whose error this
/// bound would not cover.
#[test]
fn the_lookup_matches_an_f64_lookup_of_the_same_lattices_with_one_and_two_scales() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let setup = Setup::new(&gpu, &scene);
    for filter in [
        LookupFilter::Sampler,
        LookupFilter::Texels,
        LookupFilter::SharedTexels,
    ] {
        let settings = LpvSettings {
            lookup_filter: Some(filter),
            ..ilpv(10)
        };
        for ilpv_lookup in [IlpvLookup::Accumulated, IlpvLookup::Final] {
            let one = LpvSettings {
                far_lattice: FarLattice::Off,
                ilpv_lookup,
                ..settings.clone()
            };
            let mut single = Lpv::new(&setup, one).unwrap();
            let rendered = render_indirect(&gpu, &scene, &mut single);
            let name = format!("one lattice, {filter:?}, {ilpv_lookup:?}");
            assert_lookup_matches(&gpu, &name, &[&single], &rendered);
        }
        let mut two = two_scale::TwoScale::new(&setup, settings, 5).unwrap();
        let rendered = render_indirect(&gpu, &scene, &mut two);
        let name = format!("two scales, {filter:?}");
        assert_lookup_matches(&gpu, &name, &[&two.near, &two.far], &rendered);
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn kernel_and_channel_plan_auto_measure_once_per_device_then_read_their_cache() {
    let dir = std::env::temp_dir().join(format!("vkgi-lpv-autotune-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let profile = || {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vkgi"))
            .args([
                "profile",
                "--method",
                "lpv",
                "--lattice",
                "8",
                "--frames",
                "1",
            ])
            .env("VKGI_CACHE_DIR", &dir)
            .env("VKGI_VALIDATE", "1")
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let line = stdout
            .lines()
            .find(|l| l.contains("chosen by the autotune"))
            .unwrap_or_else(|| panic!("no autotune line in {stdout}"))
            .to_string();
        let kernel = stdout
            .lines()
            .find(|l| l.contains("propagation kernel:"))
            .unwrap()
            .to_string();
        (line, kernel)
    };
    let (first, first_kernel) = profile();
    assert!(first.contains("measured now"), "{first}");
    let cache = dir.join("kernels.json");
    let entries: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cache).unwrap()).unwrap();
    let entry = entries.as_object().unwrap().values().next().unwrap();
    let chosen = serde_json::from_value::<Kernel>(entry["kernel"].clone())
        .unwrap()
        .name();
    assert!(
        first_kernel.contains(&format!("propagation kernel: {chosen}")),
        "{first_kernel} against the cache's {chosen}"
    );
    let plan = entry["plan"].as_str().unwrap().to_lowercase();
    assert!(
        first_kernel.contains(&format!("channels: {plan}")),
        "{first_kernel} against the cache's {plan}"
    );
    // Every kernel and plan was a candidate, and each line of the profile names its time.
    // The shared rows where the device allows them (lavapipe: a CPU device with shuffles) and
    // the 8³ lattice's workgroups, 8 wide, hold whole subgroups.
    let gpu = common::gpu();
    let mut candidates = vec![
        "tiled separate",
        "tiled fused",
        "naive separate",
        "naive fused",
        "column separate",
        "column fused",
        "single-column separate",
        "single-column fused",
    ];
    if shared_rows_possible(&gpu) && gpu.info.subgroup_size <= 8 {
        candidates.extend(["shared-rows separate", "shared-rows fused"]);
    }
    assert_eq!(
        entry["timings"].as_array().unwrap().len(),
        candidates.len(),
        "{entry}"
    );
    for candidate in candidates {
        // Each time follows ": " (the first) or ", " (the rest), so "column fused" cannot
        // match inside "single-column fused".
        assert!(
            first.contains(&format!(": {candidate} "))
                || first.contains(&format!(", {candidate} ")),
            "{first}"
        );
    }
    let (second, second_kernel) = profile();
    assert!(second.contains("cached in"), "{second}");
    assert_eq!(first_kernel, second_kernel);
    // A cache that is not JSON is measured around and rewritten, not an error.
    std::fs::write(&cache, "not json").unwrap();
    let (third, _) = profile();
    assert!(third.contains("measured now"), "{third}");
    assert!(
        serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(&cache).unwrap())
            .is_ok()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Where direct lighting is a fragment pass, the lookup is drawn inside it (one pass, the
/// G-buffer read once): the same HDR and 8-bit images as direct lighting followed by the lookup
/// apart (`lookup_apart`), for LPV and ILPV's two scales, with direct light and indirect alone,
/// in a matte and a glossy scene. A scene whose direct lighting is a compute pass (a point light's
/// six shadow views do not fit the fragment form's varyings) draws the lookup apart either way.
#[test]
fn the_lookup_inside_direct_lighting_gives_the_image_of_the_lookup_apart() {
    const LIT: &str = "direct lighting + lpv lookup";
    let gpu = common::gpu_with(Some(vkgi::gpu::PixelPasses::Fragment));
    let mut point_lit = Scene::load("cornell").unwrap();
    point_lit.lights[0].kind = vkgi::scene::LightKind::Point;
    let scenes = [
        ("cornell", Scene::load("cornell").unwrap(), true),
        (
            "cornell-glossy",
            Scene::load("cornell-glossy").unwrap(),
            true,
        ),
        ("cornell under a point light", point_lit, false),
    ];
    for (name, scene, fragment_form) in &scenes {
        for (scheme, indirect_only, lookup_filter) in [
            (Scheme::Ilpv, false, LookupFilter::Texels),
            (Scheme::Lpv, false, LookupFilter::Texels),
            (Scheme::Ilpv, true, LookupFilter::Texels),
            (Scheme::Ilpv, false, LookupFilter::Sampler),
        ] {
            let settings = lookup_case_settings(scheme, lookup_filter);
            let run = |lookup_apart: bool| {
                let options = lookup_case_options(indirect_only, lookup_apart);
                let (frame, passes) = three_frames(&gpu, scene, options, settings.clone());
                let ldr = frame.read_ldr(&gpu).unwrap();
                (frame.read_hdr(&gpu).unwrap(), ldr, passes)
            };
            let (inside, inside_ldr, inside_passes) = run(false);
            let (apart, apart_ldr, apart_passes) = run(true);
            let has = |passes: &[String], pass: &str| passes.iter().any(|p| p == pass);
            let case =
                format!("{name}, {scheme:?}, indirect only {indirect_only}, {lookup_filter:?}");
            assert_eq!(
                has(&inside_passes, LIT),
                *fragment_form,
                "{case}: {inside_passes:?}"
            );
            assert_eq!(has(&inside_passes, "lpv lookup"), !fragment_form, "{case}");
            assert!(
                has(&apart_passes, "lpv lookup") && !has(&apart_passes, LIT),
                "{case}"
            );
            assert_equal_up_to_one_sum(&format!("{case}, inside against apart"), &inside, &apart);
            // The tone map of radiance equal to rounding: 8-bit values apart by at most one.
            let ldr_worst = inside_ldr
                .iter()
                .zip(&apart_ldr)
                .map(|(a, b)| a.abs_diff(*b))
                .max();
            assert!(
                ldr_worst <= Some(1),
                "{case}: 8-bit images differ by {ldr_worst:?}"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// `--lookup-resolution half` is the f64 upsample (`gi::lpv::upsample`) of the lookup at full
/// resolution: the texels the mirror is given are the full-resolution lookup's light per unit
/// albedo at pixels (2i, 2j), read back with the G-buffer, so pixels at even coordinates must
/// match the full lookup itself and every pixel the mirror, both within the texels' half-float
/// rounding. Inside direct lighting and apart it gives the same image. An even-sized view
/// checks its last column and row, which lie past the last texels and take those again; an
/// odd-sized one, whose last column and row hold texels of their own.
#[test]
fn the_half_resolution_lookup_is_the_f64_upsample_of_the_full_lookup() {
    use vkgi::gi::lpv::upsample::{self, HalfTexel, PixelSurface};
    use vkgi::gi::lpv::{Injection, LookupResolution};
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for (scheme, (width, height), lookup_filter) in [
        (Scheme::Ilpv, (40u32, 30u32), LookupFilter::Texels),
        (Scheme::Lpv, (40, 30), LookupFilter::Texels),
        (Scheme::Ilpv, (41, 31), LookupFilter::Texels),
        (Scheme::Ilpv, (40, 30), LookupFilter::Sampler),
    ] {
        let run = |resolution: LookupResolution, lookup_apart: bool| {
            let options = vkgi::render::FrameOptions {
                width,
                height,
                indirect_only: true,
                lookup_apart,
                ..vkgi::render::FrameOptions::default()
            };
            let settings = LpvSettings {
                scheme,
                injection: Injection::Fixed,
                rsm: 64,
                lookup_resolution: resolution,
                lookup_filter: Some(lookup_filter),
                ..LpvSettings::default()
            };
            let (frame, passes) = three_frames(&gpu, &scene, options, settings);
            let hdr = frame.read_hdr(&gpu).unwrap();
            (frame, hdr, passes)
        };
        let (frame, full, _) = run(LookupResolution::Full, false);
        let (_, half, half_passes) = run(LookupResolution::Half, false);
        let (_, half_apart, apart_passes) = run(LookupResolution::Half, true);
        let case = format!("{scheme:?} {width}x{height} {lookup_filter:?}");
        for pass in [
            "lpv half-resolution lookup",
            "direct lighting + lpv upsample",
        ] {
            assert!(
                half_passes.iter().any(|p| p == pass),
                "{case}: {half_passes:?}"
            );
        }
        assert!(
            apart_passes.iter().any(|p| p == "lpv upsample"),
            "{case}: {apart_passes:?}"
        );
        let (worst, brightest) = common::worst_difference(&half, &half_apart);
        assert!(
            worst <= 1e-6 * brightest,
            "{case}: inside and apart differ by {worst}"
        );

        let positions = frame.read_positions(&gpu).unwrap();
        let halves = |image| -> Vec<[f32; 3]> {
            let bytes = gpu.read_image(image).unwrap();
            bytemuck::cast_slice::<u8, [u16; 4]>(&bytes)
                .iter()
                .map(|p| [p[0], p[1], p[2]].map(common::half_to_f32))
                .collect()
        };
        let normals = halves(&frame.view().gbuffer.normal);
        let albedos = halves(&frame.view().gbuffer.albedo);
        let eye = frame.view().eye.position.as_dvec3();
        let pixel = |x: u32, y: u32| (y * width + x) as usize;
        // A surface pixel's light per unit albedo, its surface and albedo.
        let surface = |i: usize| -> Option<(DVec3, PixelSurface, DVec3)> {
            let p = positions[i];
            (p[3] != 0.0).then(|| {
                let albedo = DVec3::from(albedos[i].map(f64::from));
                let light = DVec3::from(full[i].map(f64::from)) / albedo;
                let position = DVec3::new(p[0].into(), p[1].into(), p[2].into());
                let normal = DVec3::from(normals[i].map(f64::from)).normalize();
                (
                    light,
                    PixelSurface::seen_from(eye, position, normal),
                    albedo,
                )
            })
        };
        let size = upsample::half_size(width, height);
        let texels: Vec<HalfTexel> = (0..size.0 * size.1)
            .map(
                |k| match surface(pixel(2 * (k % size.0), 2 * (k / size.0))) {
                    Some((light, seen, _)) => HalfTexel {
                        light,
                        distance: seen.distance,
                        normal: seen.normal,
                    },
                    None => HalfTexel::BACKGROUND,
                },
            )
            .collect();
        let brightest = full.iter().flatten().fold(0.0f32, |m, &v| m.max(v)) as f64;
        assert!(brightest > 0.0, "{case}: black");
        // Half floats carry 11 bits: 2^-11 of the value, and the pixels' albedo rounding.
        let tolerance = |expected: f64| 1e-3 * expected + 1e-5 * brightest;
        let mut checked = 0;
        for y in 0..height {
            for x in 0..width {
                let i = pixel(x, y);
                let Some((_, seen, albedo)) = surface(i) else {
                    assert_eq!(half[i], [0.0; 3], "{case}: background at ({x}, {y})");
                    continue;
                };
                let expected = albedo * upsample::upsampled_light(&texels, size, (x, y), seen);
                for c in 0..3 {
                    let got = f64::from(half[i][c]);
                    assert!(
                        (got - expected[c]).abs() <= tolerance(expected[c]),
                        "{case}: ({x}, {y}) channel {c}: GPU {got}, f64 {}",
                        expected[c]
                    );
                    if x % 2 == 0 && y % 2 == 0 {
                        let own = f64::from(full[i][c]);
                        assert!((got - own).abs() <= tolerance(own), "{case}: ({x}, {y})");
                    }
                }
                checked += 1;
            }
        }
        assert!(
            checked > (width * height / 2) as usize,
            "{case}: {checked} surface pixels"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// Direct lighting and the lookup in their compute form (a GPU's, `--pixel-passes compute`)
/// give the image of their fragment form (lavapipe's): the lookup drawn apart as a compute pass
/// after direct lighting, against the lookup inside direct lighting's fragment pass, for LPV and
/// ILPV's two scales, both ways of reading the lattices, direct light and indirect alone, in a
/// matte and a glossy scene, with no validation error.
#[test]
fn the_compute_form_of_the_per_pixel_passes_gives_the_image_of_the_fragment_form() {
    use vkgi::gpu::PixelPasses;
    const LIT: &str = "direct lighting + lpv lookup";
    let fragment_gpu = common::gpu_with(Some(PixelPasses::Fragment));
    let compute_gpu = common::gpu_with(Some(PixelPasses::Compute));
    for name in ["cornell", "cornell-glossy"] {
        let scene = Scene::load(name).unwrap();
        for (scheme, indirect_only, lookup_filter) in [
            (Scheme::Ilpv, false, LookupFilter::Texels),
            (Scheme::Lpv, false, LookupFilter::Sampler),
            (Scheme::Ilpv, true, LookupFilter::Sampler),
            (Scheme::Lpv, true, LookupFilter::Texels),
        ] {
            let settings = lookup_case_settings(scheme, lookup_filter);
            let options = lookup_case_options(indirect_only, false);
            let run = |gpu: &vkgi::gpu::Gpu| {
                let (frame, passes) = three_frames(gpu, &scene, options.clone(), settings.clone());
                (frame.read_hdr(gpu).unwrap(), passes)
            };
            let (fragment, fragment_passes) = run(&fragment_gpu);
            let (compute, compute_passes) = run(&compute_gpu);
            let case =
                format!("{name}, {scheme:?}, indirect only {indirect_only}, {lookup_filter:?}");
            let has = |passes: &[String], pass: &str| passes.iter().any(|p| p == pass);
            assert!(has(&fragment_passes, LIT), "{case}: {fragment_passes:?}");
            assert!(
                has(&compute_passes, "lpv lookup") && !has(&compute_passes, LIT),
                "{case}: {compute_passes:?}"
            );
            assert_equal_up_to_one_sum(
                &format!("{case}, fragment against compute"),
                &fragment,
                &compute,
            );
        }
    }
    common::assert_no_validation_errors(&fragment_gpu);
    common::assert_no_validation_errors(&compute_gpu);
}

/// The lookup with texels shared across the subgroup (`--lookup-filter shared-texels`, the
/// default on lavapipe) gives the bits of the per-pixel texel lookup: LPV and ILPV's two scales,
/// inside direct lighting and apart, in the fragment and the compute form, at full and half
/// resolution, at 41x31, whose last column and row leave lanes of their batches without a pixel
/// (and the compute form's background pixels leave theirs), with no validation error.
#[test]
fn texels_shared_across_the_subgroup_give_the_bits_of_the_per_pixel_lookup() {
    use vkgi::gi::lpv::LookupResolution;
    use vkgi::gpu::PixelPasses;
    let fragment_gpu = common::gpu_with(Some(PixelPasses::Fragment));
    let compute_gpu = common::gpu_with(Some(PixelPasses::Compute));
    let scene = Scene::load("cornell").unwrap();
    let forms = [
        (
            "inside direct lighting",
            &fragment_gpu,
            false,
            LookupResolution::Full,
        ),
        ("apart", &fragment_gpu, true, LookupResolution::Full),
        (
            "apart, compute form",
            &compute_gpu,
            true,
            LookupResolution::Full,
        ),
        (
            "at half resolution",
            &fragment_gpu,
            false,
            LookupResolution::Half,
        ),
    ];
    for (form, gpu, lookup_apart, resolution) in forms {
        for scheme in [Scheme::Lpv, Scheme::Ilpv] {
            let run = |filter: LookupFilter| {
                let settings = LpvSettings {
                    lookup_resolution: resolution,
                    ..lookup_case_settings(scheme, filter)
                };
                let options = vkgi::render::FrameOptions {
                    width: 41,
                    height: 31,
                    ..lookup_case_options(false, lookup_apart)
                };
                let (frame, _) = three_frames(gpu, &scene, options, settings);
                frame.read_hdr(gpu).unwrap()
            };
            let per_pixel = run(LookupFilter::Texels);
            let shared = run(LookupFilter::SharedTexels);
            let case = format!("{scheme:?}, {form}");
            assert!(common::mean(&per_pixel) > 0.0, "{case}: black");
            let (worst, brightest) = common::worst_difference(&per_pixel, &shared);
            assert!(
                per_pixel == shared,
                "{case}: differs by up to {worst} (brightest {brightest})"
            );
        }
    }
    common::assert_no_validation_errors(&fragment_gpu);
    common::assert_no_validation_errors(&compute_gpu);
}

/// A device whose fragment or compute shaders cannot ballot, vote and shuffle across a subgroup,
/// or whose subgroups have fewer than eight lanes, looks up texels pixel by pixel by default, and
/// `--lookup-filter shared-texels` is refused there in one line.
#[test]
fn shared_texels_need_subgroups_of_eight_lanes_that_shuffle_in_pixel_shaders() {
    let mut gpu = common::gpu();
    assert!(gpu.info.pixel_subgroup_shuffles, "lavapipe has them");
    assert_eq!(LookupFilter::for_device(&gpu), LookupFilter::SharedTexels);
    let scene = Scene::load("cornell").unwrap();
    let settings = lookup_case_settings(Scheme::Lpv, LookupFilter::SharedTexels);
    for (shuffles, lanes) in [(false, 8), (true, 4)] {
        gpu.info.pixel_subgroup_shuffles = shuffles;
        gpu.info.subgroup_size = lanes;
        assert_eq!(LookupFilter::for_device(&gpu), LookupFilter::Texels);
        let error = match Lpv::new(&Setup::new(&gpu, &scene), settings.clone()) {
            Ok(_) => panic!("shared texels were looked up in subgroups that cannot share them"),
            Err(e) => format!("{e:#}"),
        };
        assert!(
            error.contains("shared-texels") && error.contains("shuffle"),
            "{error}"
        );
        assert!(!error.contains('\n'), "{error}");
    }
    common::assert_no_validation_errors(&gpu);
}

/// The LPV settings of the per-pixel pass comparisons: fixed-point injection (the same sums on
/// every run), a 64² RSM, the lattices read `lookup_filter`'s way.
fn lookup_case_settings(scheme: Scheme, lookup_filter: LookupFilter) -> LpvSettings {
    LpvSettings {
        scheme,
        injection: vkgi::gi::lpv::Injection::Fixed,
        rsm: 64,
        lookup_filter: Some(lookup_filter),
        ..LpvSettings::default()
    }
}

/// The 40x30 frame of the per-pixel pass comparisons.
fn lookup_case_options(indirect_only: bool, lookup_apart: bool) -> vkgi::render::FrameOptions {
    vkgi::render::FrameOptions {
        width: 40,
        height: 30,
        indirect_only,
        lookup_apart,
        ..vkgi::render::FrameOptions::default()
    }
}

/// Fail `case` unless `b` is lit and equals `a` up to the rounding of one sum (a blend's
/// against a shader's): 1e-6 of the brightest pixel.
fn assert_equal_up_to_one_sum(case: &str, a: &[[f32; 3]], b: &[[f32; 3]]) {
    assert!(common::mean(b) > 0.0, "{case}: black");
    let (worst, brightest) = common::worst_difference(a, b);
    assert!(
        worst <= 1e-6 * brightest,
        "{case}: differs by {worst} (brightest {brightest})"
    );
}

/// Three timed frames (no warm-up) of LPV `settings` (one lattice or two scales) in `scene`: the
/// frame and the names of the passes the profiler saw.
fn three_frames(
    gpu: &vkgi::gpu::Gpu,
    scene: &Scene,
    options: vkgi::render::FrameOptions,
    settings: LpvSettings,
) -> (vkgi::render::Frame, Vec<String>) {
    let mut frame = vkgi::render::Frame::new(gpu, scene, options).unwrap();
    let mut method = two_scale::create(&Setup::new(gpu, scene), settings).unwrap();
    let passes = common::run_naming_passes(gpu, &mut frame, method.as_mut(), 3);
    (frame, passes)
}
