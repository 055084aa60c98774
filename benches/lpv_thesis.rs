//! Seed 000's quality experiments, measured (spec 000 §8.5 and its test plan's item 7; issue #12
//! item 3): ILPV on the Cornell box at 32³ for λ_incr × propagation steps per frame, each run
//! until its incremental blend has settled.
//!
//! * Fig. 2: the mean absolute error of the tone-mapped full image (v/(1+v), sRGB, in [0, 1];
//!   the thesis does not state its unit) against the thesis's reference, 32 steps at λ 0, next
//!   to the thesis's 0.128 / 0.067 / 0.037 (4 steps) and 0.097 / 0.037 / 0.026 (8 steps) for
//!   λ 0 / 0.5 / 0.8.
//! * The λ × steps matrix of its Fig. 3 (λ 0, 0.5, 0.9 × 1, 4, 8, 32 steps) with λ 0.8 added.
//! * Each configuration also against the path tracer: relMSE of the indirect light (the frame
//!   minus the same frame without GI) against the `--bounces 1` reference's indirect part.
//!
//! Both lookups: the thesis's (`final`, the last step's lattice scaled by its mean depth) and
//! vkgi's default (`accumulated`).
//!
//! cargo bench --bench lpv_thesis [-- OUT_DIR]   (markdown to stdout, plots into OUT_DIR,
//! docs/images by default; about ten minutes on lavapipe with 2 cores)

mod common;

use std::path::Path;

use vkgi::gi::GiMethod;
use vkgi::gi::lpv::entry::settle_frames;
use vkgi::gi::lpv::technique::IlpvLookup;
use vkgi::gi::lpv::{Lpv, LpvSettings};
use vkgi::gi::registry::Setup;
use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::imageio::HdrImage;
use vkgi::metrics;
use vkgi::metrics::plot::{Series, write_plot};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

const SIZE: (u32, u32) = (96, 72);
const SPP: u32 = 512;
const LATTICE: u32 = 32;
const LAMBDAS: [f32; 4] = [0.0, 0.5, 0.8, 0.9];
const STEPS: [u32; 5] = [1, 4, 8, 16, 32];
/// The thesis's Fig. 2: (steps, [MAE at λ 0, 0.5, 0.8]).
const THESIS_FIG2: [(u32, [f64; 3]); 2] = [(4, [0.128, 0.067, 0.037]), (8, [0.097, 0.037, 0.026])];

/// One settled configuration.
struct Run {
    lambda: f32,
    steps: u32,
    full: HdrImage,
    indirect: HdrImage,
}

fn main() -> anyhow::Result<()> {
    let out_dir = common::out_dir()?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = Scene::load("cornell")?;
    println!("device: {}\n", gpu.info.name);
    let truth = common::indirect_reference(&gpu, &scene, SIZE, SPP)?;
    let direct = render(&gpu, &scene, None, 1)?;
    for lookup in [IlpvLookup::Final, IlpvLookup::Accumulated] {
        let mut runs = Vec::new();
        for lambda in LAMBDAS {
            for steps in STEPS {
                let settings = LpvSettings {
                    lattice: LATTICE,
                    iterations: steps,
                    incremental: lambda,
                    ilpv_lookup: lookup,
                    ..LpvSettings::default()
                };
                let mut lpv = Lpv::new(&Setup::new(&gpu, &scene), settings)?;
                // Twice the frames the blend needs to reach 1%: within 1e-4 of its steady state.
                let frames = 2 * settle_frames(f64::from(lambda));
                let full = render(&gpu, &scene, Some(&mut lpv), frames)?;
                let indirect = difference(&full, &direct);
                runs.push(Run {
                    lambda,
                    steps,
                    full,
                    indirect,
                });
            }
        }
        report(&out_dir, lookup, &runs, &truth)?;
    }
    Ok(())
}

/// The HDR frame after `frames` frames of `method` (direct light alone without one).
fn render(
    gpu: &Gpu,
    scene: &Scene,
    mut method: Option<&mut Lpv>,
    frames: u32,
) -> anyhow::Result<HdrImage> {
    let options = FrameOptions {
        width: SIZE.0,
        height: SIZE.1,
        ..FrameOptions::default()
    };
    let mut frame = Frame::new(gpu, scene, options)?;
    let mut ring = FrameRing::new(gpu, 2)?;
    for _ in 0..frames {
        let gi = method.as_deref_mut().map(|m| m as &mut dyn GiMethod);
        frame.submit(gpu, &mut ring, gi)?;
    }
    ring.finish()?;
    Ok(HdrImage::new(SIZE.0, SIZE.1, frame.read_hdr(gpu)?))
}

fn difference(a: &HdrImage, b: &HdrImage) -> HdrImage {
    let pixels = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(x, y)| [0, 1, 2].map(|c| x[c] - y[c]))
        .collect();
    HdrImage::new(a.width, a.height, pixels)
}

/// Mean absolute difference of the tone-mapped sRGB images, in [0, 1].
fn tone_mapped_mae(a: &HdrImage, b: &HdrImage) -> f64 {
    let (a, b) = (metrics::tonemap_srgb8(a), metrics::tonemap_srgb8(b));
    let sum: f64 = a
        .iter()
        .zip(&b)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum();
    sum / 255.0 / a.len() as f64
}

fn rel_mse(test: &HdrImage, truth: &HdrImage) -> f64 {
    metrics::compare(test, truth, None).map_or(f64::NAN, |m| m.rel_mse)
}

/// The tables and plots of one lookup.
fn report(
    out_dir: &Path,
    lookup: IlpvLookup,
    runs: &[Run],
    truth: &HdrImage,
) -> anyhow::Result<()> {
    let name = match lookup {
        IlpvLookup::Final => "final",
        IlpvLookup::Accumulated => "accumulated",
    };
    let find =
        |lambda: f32, steps: u32| runs.iter().find(|r| r.lambda == lambda && r.steps == steps);
    let Some(thesis_reference) = find(0.0, 32) else {
        anyhow::bail!("no 32-step λ 0 run");
    };
    let mae = |r: &Run| tone_mapped_mae(&r.full, &thesis_reference.full);
    println!("## Lookup `{name}`, lattice {LATTICE}³\n");
    println!("Fig. 2: MAE against 32 steps at λ 0 (thesis in brackets)\n");
    println!("| steps | λ 0 | λ 0.5 | λ 0.8 |");
    println!("|---|---|---|---|");
    for (steps, thesis) in THESIS_FIG2 {
        let cells: Vec<String> = [0.0, 0.5, 0.8]
            .iter()
            .zip(thesis)
            .map(|(&lambda, t)| {
                find(lambda, steps).map_or("-".into(), |r| format!("{:.3} ({t})", mae(r)))
            })
            .collect();
        println!("| {steps} | {} |", cells.join(" | "));
    }
    println!(
        "\nλ × steps: MAE against 32 steps at λ 0 / indirect relMSE against the path tracer\n"
    );
    let header: Vec<String> = STEPS.iter().map(|s| format!("{s} steps")).collect();
    println!("| λ | {} |", header.join(" | "));
    println!("|---|{}", "---|".repeat(STEPS.len()));
    let mut mae_series = Vec::new();
    let mut truth_series = Vec::new();
    for (colour, lambda) in LAMBDAS.into_iter().enumerate() {
        let row: Vec<&Run> = STEPS.iter().filter_map(|&s| find(lambda, s)).collect();
        let cells: Vec<String> = row
            .iter()
            .map(|r| format!("{:.3} / {:.3}", mae(r), rel_mse(&r.indirect, truth)))
            .collect();
        println!("| {lambda} | {} |", cells.join(" | "));
        let label = format!("λ {lambda}");
        // The 32-step λ 0 run is the MAE reference itself (0, off a log axis).
        let mae_points = row
            .iter()
            .map(|r| (f64::from(r.steps), mae(r)))
            .filter(|p| p.1 > 0.0);
        mae_series.push(Series::line(&label, colour, mae_points.collect()));
        let truth_points = row
            .iter()
            .map(|r| (f64::from(r.steps), rel_mse(&r.indirect, truth)));
        truth_series.push(Series::line(&label, colour, truth_points.collect()));
    }
    println!();
    write_plot(
        &out_dir.join(format!("lpv-fig2-mae-{name}.png")),
        &format!("ILPV {LATTICE}³ ({name} lookup): MAE against 32 steps at λ 0"),
        "propagation steps per frame",
        "MAE (tone-mapped)",
        mae_series,
    )?;
    write_plot(
        &out_dir.join(format!("lpv-fig2-path-tracer-{name}.png")),
        &format!("ILPV {LATTICE}³ ({name} lookup): indirect relMSE against the path tracer"),
        "propagation steps per frame",
        "relMSE",
        truth_series,
    )
}
