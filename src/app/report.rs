//! `vkgi report`: every GI method over a grid of its settings, scored against the cached
//! reference (indirect light alone and the full image), timed with the GPU profiler, written as
//! report.md, report.json, plots and an image strip.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use serde::Serialize;

use crate::frame::{Frame, FrameOptions};
use crate::gi::lpv::{Lpv, LpvSettings, Scheme};
use crate::gpu::Gpu;
use crate::gpu::frames::FrameRing;
use crate::gpu::profiler::summarize;
use crate::imageio::{self, HdrImage};
use crate::metrics::plot::{PALETTE, Plot, Series, pareto_front};
use crate::metrics::{self, Metrics};
use crate::reference::cache::{self, CacheRecord};
use crate::reference::{Bounces, PathTracer, ProgressBar, ReferenceImages, ReferenceSettings};
use crate::scene::Scene;

use super::cli::ReportArgs;

/// What the report covers.
#[derive(Clone, Debug)]
pub struct ReportConfig {
    pub scene: String,
    pub out_dir: PathBuf,
    pub size: (u32, u32),
    pub spp: u32,
    pub methods: Vec<Scheme>,
    pub lattices: Vec<u32>,
    pub iterations: Vec<u32>,
    pub incrementals: Vec<f32>,
    /// Frames per ILPV run; None: enough for the blend to settle (λ^frames < 1%).
    pub frames: Option<u32>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReportRow {
    pub method: Scheme,
    pub lattice: u32,
    pub iterations: u32,
    /// λ_incr (ILPV only).
    pub incremental: Option<f32>,
    pub frames: u32,
    /// Median GPU time of a frame (raster passes included), milliseconds.
    pub ms_per_frame: f64,
    /// Median time of one propagation step of one channel per cell, nanoseconds.
    pub ns_per_cell_step: f64,
    pub cells: usize,
    pub indirect: Metrics,
    pub full: Metrics,
    /// The full image, tone-mapped (relative to the report folder).
    pub image: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReportReference {
    pub spp: u32,
    pub bounces: u32,
    pub seconds: f64,
    pub reused: bool,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub scene: String,
    pub device: String,
    pub size: (u32, u32),
    pub reference: ReportReference,
    /// The best constant ambient term (albedo times one k fitted to the reference).
    pub ambient: Metrics,
    pub rows: Vec<ReportRow>,
}

/// Frames for the ILPV blend to settle: λ^frames below 1%, at least 4.
fn settle_frames(incremental: f32) -> u32 {
    if incremental <= 0.0 {
        return 4;
    }
    ((0.01f64.ln() / f64::from(incremental).ln()).ceil() as u32 + 1).max(4)
}

fn method_name(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Lpv => "lpv",
        Scheme::Ilpv => "ilpv",
    }
}

/// The reference at `dir/reference.exr`: reused if its sidecar matches, else rendered.
fn reference(
    gpu: &Gpu,
    scene: &Scene,
    config: &ReportConfig,
) -> anyhow::Result<(ReferenceImages, ReportReference)> {
    let settings = ReferenceSettings {
        width: config.size.0,
        height: config.size.1,
        spp: config.spp,
        bounces: Bounces::Limited(1),
        seed: 1,
    };
    let path = config.out_dir.join("reference.exr");
    let key = cache::key(scene, &settings);
    if let Some(images) = cache::load(&path, &key) {
        let seconds = std::fs::read_to_string(cache::sidecar_path(&path))
            .ok()
            .and_then(|t| serde_json::from_str::<CacheRecord>(&t).ok())
            .map_or(0.0, |r| r.seconds);
        let info = ReportReference {
            spp: config.spp,
            bounces: 1,
            seconds,
            reused: true,
        };
        return Ok((images, info));
    }
    let mut tracer = PathTracer::new(gpu, scene, settings.width, settings.height)?;
    let mut bar = ProgressBar::new("reference");
    let start = Instant::now();
    let images = tracer.render(gpu, &settings, |d, t| bar.update(d, t))?;
    let seconds = start.elapsed().as_secs_f64();
    let record = CacheRecord {
        key,
        split: true,
        seconds,
        device: gpu.info.name.clone(),
    };
    cache::store(&path, &images, &record)?;
    Ok((
        images,
        ReportReference {
            spp: config.spp,
            bounces: 1,
            seconds,
            reused: false,
        },
    ))
}

/// Per-pixel albedo of what each pixel sees (0 for background), by CPU ray casting.
pub fn albedo_image(scene: &Scene, width: u32, height: u32) -> Vec<[f32; 3]> {
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let dir = scene.camera.ray_direction(
                glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
                width,
                height,
            );
            scene
                .mesh
                .intersect(scene.camera.position, dir, 1e-4, 1e9)
                .map_or([0.0; 3], |hit| {
                    scene.materials[scene.mesh.materials[hit.triangle] as usize]
                        .albedo
                        .to_array()
                })
        })
        .collect()
}

/// Albedo times the k that minimises the squared error against `truth`.
pub fn constant_ambient(albedo: &[[f32; 3]], truth: &HdrImage) -> HdrImage {
    let (num, den) = albedo
        .iter()
        .zip(&truth.pixels)
        .fold((0.0f64, 0.0f64), |(n, d), (a, t)| {
            (0..3).fold((n, d), |(n, d), c| {
                (n + f64::from(a[c] * t[c]), d + f64::from(a[c] * a[c]))
            })
        });
    let k = if den > 0.0 { (num / den) as f32 } else { 0.0 };
    HdrImage::new(
        truth.width,
        truth.height,
        albedo.iter().map(|a| a.map(|v| v * k)).collect(),
    )
}

fn add(a: &HdrImage, b: &HdrImage) -> HdrImage {
    let pixels = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| [p[0] + q[0], p[1] + q[1], p[2] + q[2]])
        .collect();
    HdrImage::new(a.width, a.height, pixels)
}

fn write_tonemapped(path: &Path, image: &HdrImage) -> anyhow::Result<()> {
    let rgba: Vec<u8> = metrics::tonemap_srgb8(image)
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    imageio::write_png(path, image.width, image.height, &rgba)
}

/// Render the direct light (no GI) once.
fn direct_image(gpu: &Gpu, scene: &Scene, frame: &Frame) -> anyhow::Result<HdrImage> {
    let options = FrameOptions {
        indirect_only: false,
        ..frame.options.clone()
    };
    let direct = Frame::new(gpu, scene, options)?;
    let mut ring = FrameRing::new(gpu, gpu.queues.graphics, 2)?;
    direct.submit(gpu, &mut ring, None)?;
    ring.finish()?;
    Ok(HdrImage::new(
        direct.options.width,
        direct.options.height,
        direct.read_hdr(gpu)?,
    ))
}

/// One configuration: its indirect image, frame time and step time per cell.
fn run_config(
    gpu: &Gpu,
    scene: &Scene,
    frame: &Frame,
    settings: LpvSettings,
    frames: u32,
) -> anyhow::Result<(HdrImage, f64, f64, usize)> {
    let mut lpv = Lpv::new(gpu, scene, settings)?;
    let mut ring = FrameRing::new(gpu, gpu.queues.graphics, 2)?;
    // The first frame compiles shaders on some drivers: not timed.
    frame.submit(gpu, &mut ring, Some(&mut lpv))?;
    ring.finish()?;
    ring.profiler.clear();
    for _ in 1..frames.max(2) {
        frame.submit(gpu, &mut ring, Some(&mut lpv))?;
    }
    ring.finish()?;
    let report = ring.profiler.report();
    let frame_ms = report.frame.as_ref().map_or(0.0, |f| f.median_ns / 1e6);
    let steps: Vec<f64> = report
        .passes
        .iter()
        .filter(|p| p.name.starts_with("propagate "))
        .flat_map(|p| p.per_frame_ns.iter().copied())
        .collect();
    let cells = lpv.lattice.cell_count();
    let step_ns = summarize("step", steps.len(), steps).median_ns / cells as f64;
    let image = HdrImage::new(
        frame.options.width,
        frame.options.height,
        frame.read_hdr(gpu)?,
    );
    Ok((image, frame_ms, step_ns, cells))
}

/// Run the whole report.
pub fn run(gpu: &Gpu, config: &ReportConfig) -> anyhow::Result<Report> {
    let scene = Scene::load(&config.scene)?;
    std::fs::create_dir_all(config.out_dir.join("images"))
        .with_context(|| format!("creating {}", config.out_dir.display()))?;
    let (truth, reference_info) = reference(gpu, &scene, config)?;
    let truth_full = truth.combined();
    let (w, h) = config.size;
    let frame = Frame::new(
        gpu,
        &scene,
        FrameOptions {
            width: w,
            height: h,
            indirect_only: true,
            ..FrameOptions::default()
        },
    )?;
    let direct = direct_image(gpu, &scene, &frame)?;
    let albedo = albedo_image(&scene, w, h);
    let ambient = metrics::compare(
        &constant_ambient(&albedo, &truth.indirect),
        &truth.indirect,
        None,
    )?;

    let mut grid: Vec<LpvSettings> = Vec::new();
    for &scheme in &config.methods {
        for &lattice in &config.lattices {
            for &iterations in &config.iterations {
                let lambdas: Vec<f32> = match scheme {
                    Scheme::Ilpv => config.incrementals.clone(),
                    Scheme::Lpv => vec![0.0],
                };
                for incremental in lambdas {
                    grid.push(LpvSettings {
                        scheme,
                        lattice,
                        iterations,
                        incremental,
                        ..LpvSettings::default()
                    });
                }
            }
        }
    }
    let mut bar = ProgressBar::counting("report", "configurations");
    let mut rows = Vec::new();
    for (i, settings) in grid.iter().enumerate() {
        let frames = match settings.scheme {
            Scheme::Ilpv => config
                .frames
                .unwrap_or_else(|| settle_frames(settings.incremental)),
            Scheme::Lpv => 3,
        };
        let (indirect, ms, ns_per_cell, cells) =
            run_config(gpu, &scene, &frame, settings.clone(), frames)?;
        let full = add(&direct, &indirect);
        let name = match settings.scheme {
            Scheme::Ilpv => format!(
                "ilpv-l{}-i{}-lambda{}.png",
                settings.lattice, settings.iterations, settings.incremental
            ),
            Scheme::Lpv => format!("lpv-l{}-i{}.png", settings.lattice, settings.iterations),
        };
        let image = format!("images/{name}");
        write_tonemapped(&config.out_dir.join(&image), &full)?;
        rows.push(ReportRow {
            method: settings.scheme,
            lattice: settings.lattice,
            iterations: settings.iterations,
            incremental: (settings.scheme == Scheme::Ilpv).then_some(settings.incremental),
            frames,
            ms_per_frame: ms,
            ns_per_cell_step: ns_per_cell,
            cells,
            indirect: metrics::compare(&indirect, &truth.indirect, None)?,
            full: metrics::compare(&full, &truth_full, None)?,
            image,
        });
        bar.update(i as u32 + 1, grid.len() as u32);
    }
    let report = Report {
        scene: scene.name.clone(),
        device: gpu.info.name.clone(),
        size: config.size,
        reference: reference_info,
        ambient,
        rows,
    };
    write_outputs(gpu, &scene, config, &report, &direct, &truth, &frame)?;
    Ok(report)
}

fn write_outputs(
    gpu: &Gpu,
    scene: &Scene,
    config: &ReportConfig,
    report: &Report,
    direct: &HdrImage,
    truth: &ReferenceImages,
    frame: &Frame,
) -> anyhow::Result<()> {
    let dir = &config.out_dir;
    imageio::write_text(
        &dir.join("report.json"),
        &serde_json::to_string_pretty(report)?,
    )?;
    imageio::write_text(&dir.join("report.md"), &markdown(report))?;
    write_plots(dir, report)?;
    write_strip(gpu, scene, dir, direct, truth, frame)
}

fn markdown(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# vkgi report: {}\n", report.scene);
    let _ = writeln!(
        out,
        "Device: {}. Image {}x{}. Reference: path tracer, {} spp, bounces {} ({}, {:.1} s).\n",
        report.device,
        report.size.0,
        report.size.1,
        report.reference.spp,
        report.reference.bounces,
        if report.reference.reused {
            "reused from the cache"
        } else {
            "rendered"
        },
        report.reference.seconds
    );
    let _ = writeln!(
        out,
        "Best constant ambient term (albedo x k fitted to the reference), indirect light: RMSE {:.5}, relMSE {:.5}, FLIP {:.4}.\n",
        report.ambient.rmse, report.ambient.rel_mse, report.ambient.flip
    );
    let _ = writeln!(
        out,
        "![error against time](error_vs_time.png)\n\n![ns per cell](ns_per_cell.png)\n\n![strip](strip.png)\n"
    );
    let _ = writeln!(
        out,
        "| method | lattice | steps | λ_incr | frames | ms/frame | ns/cell/step | indirect RMSE | indirect relMSE | indirect FLIP | full RMSE | full relMSE | full FLIP | image |"
    );
    let _ = writeln!(
        out,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for r in &report.rows {
        let lambda = r.incremental.map_or("-".to_string(), |l| format!("{l}"));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.5} | {:.5} | {:.4} | {:.5} | {:.5} | {:.4} | [png]({}) |",
            method_name(r.method),
            r.lattice,
            r.iterations,
            lambda,
            r.frames,
            r.ms_per_frame,
            r.ns_per_cell_step,
            r.indirect.rmse,
            r.indirect.rel_mse,
            r.indirect.flip,
            r.full.rmse,
            r.full.rel_mse,
            r.full.flip,
            r.image
        );
    }
    out
}

fn write_plots(dir: &Path, report: &Report) -> anyhow::Result<()> {
    let all: Vec<(f64, f64)> = report
        .rows
        .iter()
        .map(|r| (r.ms_per_frame, r.indirect.rmse))
        .collect();
    let front = pareto_front(&all);
    let mut series = Vec::new();
    for (k, scheme) in [Scheme::Lpv, Scheme::Ilpv].into_iter().enumerate() {
        let idx: Vec<usize> = (0..report.rows.len())
            .filter(|&i| report.rows[i].method == scheme)
            .collect();
        if idx.is_empty() {
            continue;
        }
        series.push(Series {
            label: method_name(scheme).to_string(),
            points: idx.iter().map(|&i| all[i]).collect(),
            marked: idx.iter().map(|&i| front[i]).collect(),
            connect: false,
            colour: PALETTE[k],
        });
    }
    let plot = Plot {
        title: format!(
            "{}: indirect RMSE against GPU ms per frame (ringed: Pareto front)",
            report.scene
        ),
        x_label: "ms per frame".into(),
        y_label: "indirect RMSE".into(),
        series,
    };
    let img = plot.render();
    imageio::write_atomically(&dir.join("error_vs_time.png"), |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .context("writing the plot")
    })?;

    let mut series = Vec::new();
    for (k, scheme) in [Scheme::Lpv, Scheme::Ilpv].into_iter().enumerate() {
        let mut by_lattice: Vec<(u32, usize, Vec<f64>)> = Vec::new();
        for r in report
            .rows
            .iter()
            .filter(|r| r.method == scheme && r.ns_per_cell_step > 0.0)
        {
            match by_lattice.iter_mut().find(|e| e.0 == r.lattice) {
                Some(e) => e.2.push(r.ns_per_cell_step),
                None => by_lattice.push((r.lattice, r.cells, vec![r.ns_per_cell_step])),
            }
        }
        by_lattice.sort_by_key(|e| e.1);
        if by_lattice.is_empty() {
            continue;
        }
        series.push(Series {
            label: method_name(scheme).to_string(),
            points: by_lattice
                .into_iter()
                .map(|(_, cells, v)| (cells as f64, summarize("", v.len(), v).median_ns))
                .collect(),
            marked: Vec::new(),
            connect: true,
            colour: PALETTE[k],
        });
    }
    let plot = Plot {
        title: format!(
            "{}: propagation ns per cell per step against lattice cells",
            report.scene
        ),
        x_label: "lattice cells".into(),
        y_label: "ns per cell per step".into(),
        series,
    };
    let img = plot.render();
    imageio::write_atomically(&dir.join("ns_per_cell.png"), |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .context("writing the plot")
    })
}

/// Reference, each method at its default settings, and their FLIP error maps, side by side.
fn write_strip(
    gpu: &Gpu,
    scene: &Scene,
    dir: &Path,
    direct: &HdrImage,
    truth: &ReferenceImages,
    frame: &Frame,
) -> anyhow::Result<()> {
    let reference = truth.combined();
    let mut panels: Vec<(String, Vec<u8>)> =
        vec![("reference".into(), metrics::tonemap_srgb8(&reference))];
    let mut maps = Vec::new();
    for scheme in [Scheme::Ilpv, Scheme::Lpv] {
        let settings = LpvSettings {
            scheme,
            ..LpvSettings::default()
        };
        let frames = match scheme {
            Scheme::Ilpv => settle_frames(settings.incremental),
            Scheme::Lpv => 2,
        };
        let (indirect, _, _, _) = run_config(gpu, scene, frame, settings, frames)?;
        let full = add(direct, &indirect);
        panels.push((
            method_name(scheme).to_string(),
            metrics::tonemap_srgb8(&full),
        ));
        let rgb: Vec<u8> = metrics::flip_heatmap(&full, &reference)
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        maps.push((format!("{} flip", method_name(scheme)), rgb));
    }
    panels.extend(maps);
    let (w, h) = (reference.width, reference.height);
    let label_height = 12;
    let mut strip = image::RgbImage::from_pixel(
        w * panels.len() as u32,
        h + label_height,
        image::Rgb([255, 255, 255]),
    );
    for (k, (label, rgb)) in panels.iter().enumerate() {
        for y in 0..h {
            for x in 0..w {
                let i = ((y * w + x) * 3) as usize;
                strip.put_pixel(
                    k as u32 * w + x,
                    y,
                    image::Rgb([rgb[i], rgb[i + 1], rgb[i + 2]]),
                );
            }
        }
        crate::metrics::plot::label(&mut strip, (k as u32 * w + 4) as i32, (h + 4) as i32, label);
    }
    imageio::write_atomically(&dir.join("strip.png"), |tmp| {
        strip
            .save_with_format(tmp, image::ImageFormat::Png)
            .context("writing the strip")
    })
}

/// `vkgi report`.
pub fn run_command(args: &ReportArgs) -> anyhow::Result<()> {
    if args.spp == 0 {
        crate::bad_input!("--spp must be at least 1");
    }
    if args.lattice.is_empty()
        || args.iterations.is_empty()
        || args.incremental.is_empty()
        || args.method.is_empty()
    {
        crate::bad_input!("--method, --lattice, --iterations and --incremental each need a value");
    }
    let config = ReportConfig {
        scene: args.scene.clone(),
        out_dir: args.out_dir.clone(),
        size: args.size,
        spp: args.spp,
        methods: args.method.clone(),
        lattices: args.lattice.clone(),
        iterations: args.iterations.clone(),
        incrementals: args.incremental.clone(),
        frames: args.frames,
    };
    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let report = run(&gpu, &config)?;
    super::render::check_validation(&gpu)?;
    eprintln!(
        "report: {} configurations -> {}",
        report.rows.len(),
        config.out_dir.join("report.md").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ilpv_runs_until_the_blend_settles() {
        assert_eq!(settle_frames(0.0), 4);
        assert_eq!(settle_frames(0.5), 8);
        assert!(0.9f64.powi(settle_frames(0.9) as i32 - 1) < 0.01);
    }
}
