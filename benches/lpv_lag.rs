//! Seed 000's lag after a light jump (spec 000 §6.3 and its test plan's item 6; issue #12 item 3):
//! ILPV on the Cornell box settles with the spot where the scene puts it, the spot moves 0.2 m
//! along x, and the frames until the indirect image is within 10% and 1% of its new steady state
//! (Σ|I_f − I_new| ≤ 0.1 and 0.01 of Σ|I_old − I_new|) are counted against λ, next to the
//! estimate from the blend alone, ln 0.1 / ln λ (blocking and the lattice's borders make the old
//! light decay faster: a frame carries λ times what survives its steps), and the indirect
//! light's relMSE against the path tracer's for the moved light (256 spp, one bounce) 1, 2 and
//! 5 frames after the jump and settled. Two settings: vkgi's defaults (lattice 10, 8 steps per
//! frame) and the thesis's lag case (lattice 32, 1 step).
//!
//! cargo bench --bench lpv_lag [-- OUT_DIR]   (markdown to stdout, the plot of the remaining
//! distance per frame to OUT_DIR/lpv-lag.png, docs/images by default; about two minutes on
//! lavapipe, 2 cores)

mod common;

use vkgi::gi::lpv::{Lpv, LpvSettings};
use vkgi::gi::registry::Setup;
use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::imageio::HdrImage;
use vkgi::metrics;
use vkgi::metrics::plot::{Series, write_plot};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

const LAMBDAS: [f32; 4] = [0.5, 0.8, 0.9, 0.95];
/// (lattice, steps per frame).
const CASES: [(u32, u32); 2] = [(10, 8), (32, 1)];
const JUMP: f32 = 0.2;
const SIZE: (u32, u32) = (48, 36);

/// Σ|a − b| over every pixel and channel.
fn distance(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| f64::from((x - y).abs()))
        .sum()
}

/// Frames after the jump until the image is within `fraction` of the way from the old steady
/// state to the new one.
fn frames_to(after: &[Vec<[f32; 3]>], old: &[[f32; 3]], fraction: f64) -> Option<usize> {
    let new = after.last()?;
    let start = distance(old, new);
    after
        .iter()
        .position(|image| distance(image, new) <= fraction * start)
        .map(|f| f + 1)
}

fn main() -> anyhow::Result<()> {
    let out_dir = common::out_dir()?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    println!("device: {}\n", gpu.info.name);
    let mut moved = Scene::load("cornell")?;
    moved.lights[0].position.x += JUMP;
    let truth = common::indirect_reference(&gpu, &moved, SIZE, 256)?;
    println!("## ILPV on the Cornell box: frames after a 0.2 m jump of the spot light\n");
    println!(
        "| lattice, steps | λ | to 10% | to 1% | ln 0.1 / ln λ | ln 0.01 / ln λ | relMSE against the path tracer 1 / 2 / 5 frames after, settled |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut series = Vec::new();
    for (lattice, iterations) in CASES {
        for lambda in LAMBDAS {
            let points = lag(&gpu, &truth, lattice, iterations, lambda)?;
            let label = format!("{lattice}³, {iterations} step(s), λ {lambda}");
            series.push(Series::line(&label, series.len(), points));
        }
    }
    write_plot(
        &out_dir.join("lpv-lag.png"),
        "ILPV after a 0.2 m jump of the spot: distance left to the new steady state",
        "frames after the jump",
        "Σ|I_f − I_new| / Σ|I_old − I_new|",
        series,
    )
}

/// One row: the frames ILPV at `lattice` cells, `iterations` steps per frame and λ `lambda`
/// takes to follow the jump; returns (frame, the distance left as a fraction) per frame.
fn lag(
    gpu: &Gpu,
    truth: &HdrImage,
    lattice: u32,
    iterations: u32,
    lambda: f32,
) -> anyhow::Result<Vec<(f64, f64)>> {
    let mut scene = Scene::load("cornell")?;
    let options = FrameOptions {
        width: SIZE.0,
        height: SIZE.1,
        indirect_only: true,
        ..FrameOptions::default()
    };
    let mut frame = Frame::new(gpu, &scene, options)?;
    let settings = LpvSettings {
        lattice,
        iterations,
        incremental: lambda,
        ..LpvSettings::default()
    };
    // One lattice: the thesis's scheme.
    let mut lpv = Lpv::new(&Setup::new(gpu, &scene), settings)?;
    let mut ring = FrameRing::new(gpu, 2)?;
    // Five times the frames the blend alone needs to reach 1%.
    let settle = (5.0 * (0.01f64).ln() / f64::from(lambda).ln()).ceil() as usize;
    let mut render = |frame: &mut Frame, lpv: &mut Lpv| -> anyhow::Result<Vec<[f32; 3]>> {
        frame.submit(gpu, &mut ring, Some(lpv))?;
        ring.finish()?;
        Ok(frame.read_hdr(gpu)?)
    };
    let mut old = Vec::new();
    for _ in 0..settle {
        old = render(&mut frame, &mut lpv)?;
    }
    scene.lights[0].position.x += JUMP;
    frame.set_lights(&scene);
    let after = (0..settle)
        .map(|_| render(&mut frame, &mut lpv))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let show = |f: Option<usize>| f.map_or("-".to_string(), |f| f.to_string());
    let estimate = |fraction: f64| fraction.ln() / f64::from(lambda).ln();
    let rel_mse = |image: Option<&Vec<[f32; 3]>>| {
        image.map_or("-".to_string(), |image| {
            let test = HdrImage::new(SIZE.0, SIZE.1, image.clone());
            metrics::compare(&test, truth, None)
                .map_or("-".to_string(), |m| format!("{:.3}", m.rel_mse))
        })
    };
    println!(
        "| {lattice}, {iterations} | {lambda} | {} | {} | {:.1} | {:.1} | {} / {} / {} / {} |",
        show(frames_to(&after, &old, 0.1)),
        show(frames_to(&after, &old, 0.01)),
        estimate(0.1),
        estimate(0.01),
        rel_mse(after.first()),
        rel_mse(after.get(1)),
        rel_mse(after.get(4)),
        rel_mse(after.last())
    );
    let Some(new) = after.last() else {
        return Ok(Vec::new());
    };
    let start = distance(&old, new);
    Ok(after
        .iter()
        .enumerate()
        .map(|(f, image)| ((f + 1) as f64, distance(image, new) / start))
        .collect())
}
