//! `vkgi report`: every registered GI method (the ambient baseline among them) over a grid of
//! its settings, scored against the cached reference (indirect light alone and the full image),
//! timed with the GPU profiler, written as report.md, report.json, plots and an image strip.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use image::RgbImage;
use serde::Serialize;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::Settings;
use crate::gpu::Gpu;
use crate::imageio::{self, HdrImage};
use crate::metrics::plot::{Plot, Series, pareto_front, strip};
use crate::metrics::{self, Metrics};
use crate::reference::cache::{self, CacheRecord};
use crate::reference::{self, Bounces, ReferenceImages, ReferenceSettings, Tracer};
use crate::render::runner::run_frames;
use crate::render::{Frame, FrameOptions};
use crate::scene::Scene;

use super::cli::ReportArgs;
use super::profile::{core_pass_median, entries};

/// The registered name of the baseline every method's error is read against.
const BASELINE: &str = "ambient";

/// What the report covers.
#[derive(Clone, Debug)]
pub struct ReportConfig {
    pub scene: String,
    pub out_dir: PathBuf,
    pub size: (u32, u32),
    pub spp: u32,
    /// Registered method names (empty: every registered method).
    pub methods: Vec<String>,
    /// Setting values to sweep (settings not listed sweep their defaults' values).
    pub grid: Vec<(String, Vec<String>)>,
    /// Frames per run; None: as many as each configuration needs to settle.
    pub frames: Option<u32>,
}

/// The cost of a method's core pass (e.g. one propagation step of one channel, per cell).
#[derive(Clone, Debug, Serialize)]
pub struct CoreCost {
    pub pass: &'static str,
    pub unit: &'static str,
    pub units: usize,
    pub ns_per_unit: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReportRow {
    pub method: &'static str,
    /// The swept settings of this row, as (name, value).
    pub settings: Vec<(String, String)>,
    pub frames: u32,
    /// Median GPU time of a frame (raster passes included), milliseconds.
    pub ms_per_frame: f64,
    pub core: Option<CoreCost>,
    pub indirect: Metrics,
    pub full: Metrics,
    /// Indirect relMSE over the ambient baseline's (below 1 beats it).
    pub rel_mse_vs_ambient: Option<f64>,
    /// A row at a setting's approximate value (`Setting::approximates`: LPV's and ILPV's
    /// `--lookup-resolution half`): its indirect image against the same configuration's at the
    /// exact value (full resolution). None for other rows, or where the grid has no such row.
    pub vs_exact_setting: Option<Metrics>,
    /// Seed 002's similarity of the full image against the same method's first row (the
    /// LightWave thesis's tables compare every setting with its default, not with the truth).
    pub similarity_vs_first: f64,
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
    pub rows: Vec<ReportRow>,
}

/// The swept settings of one configuration, as (name, value).
pub type Combination = Vec<(String, String)>;

/// Every configuration of `entry`: the combinations of the values of each setting the user
/// listed or the method sweeps by default, as (swept values, settings).
pub fn grid(
    entry: &MethodEntry,
    user: &[(String, Vec<String>)],
) -> Result<Vec<(Combination, Settings)>, InputError> {
    let mut combinations: Vec<Combination> = vec![Vec::new()];
    for setting in entry.settings {
        let values: Vec<String> = match user.iter().find(|(n, _)| n == setting.name) {
            Some((_, values)) => values.clone(),
            None => setting.sweep.iter().map(|v| v.to_string()).collect(),
        };
        if values.is_empty() {
            continue;
        }
        combinations = combinations
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut next = c.clone();
                    next.push((setting.name.to_string(), v.clone()));
                    next
                })
            })
            .collect();
    }
    combinations
        .into_iter()
        .map(|combination| {
            let settings = entry.settings(&combination)?;
            Ok((combination, settings))
        })
        .collect()
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
        strategy: Default::default(),
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
    let bar = super::progress::counting("reference", "spp");
    let start = Instant::now();
    let (images, traced_on) = reference::trace(gpu, scene, &settings, Tracer::Auto, |d, t| {
        super::progress::update(&bar, d, t)
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let record = CacheRecord {
        key,
        split: true,
        seconds,
        device: traced_on,
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

fn add(a: &HdrImage, b: &HdrImage) -> HdrImage {
    let pixels = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| [p[0] + q[0], p[1] + q[1], p[2] + q[2]])
        .collect();
    HdrImage::new(a.width, a.height, pixels)
}

fn tonemapped(image: &HdrImage) -> anyhow::Result<RgbImage> {
    RgbImage::from_raw(image.width, image.height, metrics::tonemap_srgb8(image))
        .context("tone-mapped image size")
}

fn write_png(path: &Path, image: &RgbImage) -> anyhow::Result<()> {
    imageio::write_atomically(path, |tmp| {
        image
            .save_with_format(tmp, image::ImageFormat::Png)
            .with_context(|| format!("writing {}", path.display()))
    })
}

/// Render the direct light (no GI) once.
fn direct_image(gpu: &Gpu, scene: &Scene, options: &FrameOptions) -> anyhow::Result<HdrImage> {
    let mut direct = Frame::new(
        gpu,
        scene,
        FrameOptions {
            indirect_only: false,
            ..options.clone()
        },
    )?;
    run_frames(gpu, &mut direct, None, 0, 1)?;
    Ok(HdrImage::new(
        direct.options.width,
        direct.options.height,
        direct.read_hdr(gpu)?,
    ))
}

/// What one configuration produced.
struct Run {
    indirect: HdrImage,
    ms_per_frame: f64,
    core: Option<CoreCost>,
}

/// Build `entry` with `settings` and run `frames` frames (the first untimed): its indirect
/// image, frame time and core-pass cost.
fn run_config(
    gpu: &Gpu,
    scene: &Scene,
    frame: &mut Frame,
    truth: &ReferenceImages,
    (entry, settings): (&MethodEntry, &Settings),
    frames: u32,
) -> anyhow::Result<Run> {
    let setup = Setup {
        gpu,
        scene,
        reference: Some(truth),
        progress: &|_, _| {},
    };
    let mut method = entry.create(&setup, settings)?;
    let ring = run_frames(gpu, frame, Some(method.as_mut()), 1, frames.max(2) - 1)?;
    let report = ring.profiler.report();
    let core = method.core_pass().map(|c| CoreCost {
        pass: c.pass,
        unit: c.unit,
        units: c.units,
        ns_per_unit: core_pass_median(&report, entry.name, &c) / c.units.max(1) as f64,
    });
    Ok(Run {
        indirect: HdrImage::new(
            frame.options.width,
            frame.options.height,
            frame.read_hdr(gpu)?,
        ),
        ms_per_frame: report.frame.as_ref().map_or(0.0, |f| f.median_ns / 1e6),
        core,
    })
}

/// The file name of a row's image: the method and its swept settings.
fn image_name(method: &str, settings: &[(String, String)]) -> String {
    let mut name = method.to_string();
    for (setting, value) in settings {
        name.push('-');
        name.push_str(setting);
        name.push_str(value);
    }
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("images/{safe}.png")
}

/// Run the whole report.
pub fn run(gpu: &Gpu, config: &ReportConfig) -> anyhow::Result<Report> {
    let scene = Scene::load(&config.scene)?;
    let mut plan = Vec::new();
    for entry in entries(&config.methods)? {
        for (swept, settings) in grid(entry, &config.grid)? {
            plan.push((entry, swept, settings));
        }
    }
    std::fs::create_dir_all(config.out_dir.join("images"))
        .with_context(|| format!("creating {}", config.out_dir.display()))?;
    let (truth, reference_info) = reference(gpu, &scene, config)?;
    let truth_full = truth.combined();
    let (w, h) = config.size;
    let mut frame = Frame::new(
        gpu,
        &scene,
        FrameOptions {
            width: w,
            height: h,
            indirect_only: true,
            lights_move: true,
            ..FrameOptions::default()
        },
    )?;
    let direct = direct_image(gpu, &scene, &frame.options)?;

    let bar = super::progress::counting("report", "configurations");
    let mut rows = Vec::new();
    let mut first_images: Vec<(&str, HdrImage)> = Vec::new();
    let mut unpaired: Vec<(usize, HdrImage)> = Vec::new();
    for (i, (entry, swept, settings)) in plan.iter().enumerate() {
        let frames = config
            .frames
            .unwrap_or_else(|| (entry.settle_frames)(settings));
        let run = run_config(gpu, &scene, &mut frame, &truth, (entry, settings), frames)?;
        let full = add(&direct, &run.indirect);
        let image = image_name(entry.name, swept);
        write_png(&config.out_dir.join(&image), &tonemapped(&full)?)?;
        if !first_images.iter().any(|(m, _)| *m == entry.name) {
            first_images.push((entry.name, full.clone()));
        }
        let first = &first_images
            .iter()
            .find(|(m, _)| *m == entry.name)
            .expect("kept")
            .1;
        rows.push(ReportRow {
            method: entry.name,
            settings: swept.clone(),
            frames: frames.max(2),
            ms_per_frame: run.ms_per_frame,
            core: run.core,
            indirect: metrics::compare(&run.indirect, &truth.indirect, None)?,
            full: metrics::compare(&full, &truth_full, None)?,
            rel_mse_vs_ambient: None,
            vs_exact_setting: None,
            similarity_vs_first: metrics::similarity(&full, first, None)?,
            image,
        });
        pair_approximations(entry, &mut rows, &mut unpaired, run.indirect)?;
        super::progress::update(&bar, i as u32 + 1, plan.len() as u32);
    }
    let baseline = rows
        .iter()
        .filter(|r| r.method == BASELINE)
        .map(|r| r.indirect.rel_mse)
        .fold(f64::INFINITY, f64::min);
    if baseline.is_finite() && baseline > 0.0 {
        for row in &mut rows {
            row.rel_mse_vs_ambient = Some(row.indirect.rel_mse / baseline);
        }
    }
    let report = Report {
        scene: scene.name.clone(),
        device: gpu.info.name.clone(),
        size: config.size,
        reference: reference_info,
        rows,
    };
    let dir = &config.out_dir;
    imageio::write_text(
        &dir.join("report.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    imageio::write_text(&dir.join("report.md"), &markdown(&report))?;
    write_plots(dir, &report)?;
    let strip_methods: Vec<&MethodEntry> = entries(&config.methods)?;
    write_strip(
        gpu,
        &scene,
        dir,
        (&direct, &truth),
        &mut frame,
        &strip_methods,
    )?;
    Ok(report)
}

/// The last of `rows`, a row of `entry` whose indirect image is `image`: if it sweeps a
/// setting with an approximate value (`Setting::approximates`) and the row of the same method
/// and other settings at that setting's other value is among `unpaired` (row index, indirect
/// image), score the approximate row against the exact one and drop the partner's image; else
/// keep this row's image in `unpaired` until its partner comes.
fn pair_approximations(
    entry: &MethodEntry,
    rows: &mut [ReportRow],
    unpaired: &mut Vec<(usize, HdrImage)>,
    image: HdrImage,
) -> anyhow::Result<()> {
    let last = rows.len() - 1;
    // The swept setting with an approximate value, this row's value of it and the other.
    let approximation = rows[last]
        .settings
        .iter()
        .enumerate()
        .find_map(|(k, (name, value))| {
            let (approximate, exact) = entry
                .settings
                .iter()
                .find(|s| s.name == name)?
                .approximates?;
            let other = match value.as_str() {
                v if v == approximate => exact,
                v if v == exact => approximate,
                _ => return None,
            };
            Some((k, value == approximate, other))
        });
    let Some((k, is_approximate, other)) = approximation else {
        return Ok(());
    };
    let mut wanted = rows[last].settings.clone();
    wanted[k].1 = other.to_string();
    let partner = unpaired
        .iter()
        .position(|(i, _)| rows[*i].method == entry.name && rows[*i].settings == wanted);
    match partner {
        Some(p) => {
            let (index, partner_image) = unpaired.swap_remove(p);
            let (approximate, (approximate_image, exact_image)) = if is_approximate {
                (last, (&image, &partner_image))
            } else {
                (index, (&partner_image, &image))
            };
            rows[approximate].vs_exact_setting =
                Some(metrics::compare(approximate_image, exact_image, None)?);
        }
        None => unpaired.push((last, image)),
    }
    Ok(())
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
        "`{BASELINE}` is the baseline: albedo times one constant irradiance per channel, fitted by least squares to this reference's indirect light (an oracle). \"÷ {BASELINE}\" is a row's indirect relMSE over the baseline's: below 1 beats it. \"Against the exact setting\" scores a row at an approximate setting (today `--lookup-resolution half`) against the same configuration at the value it approximates (`full`): the error the approximation adds.\n"
    );
    let _ = writeln!(
        out,
        "![error against time](error_vs_time.png)\n\n![ns per unit](ns_per_unit.png)\n\n![strip](strip.png)\n"
    );
    let _ = writeln!(
        out,
        "| method | settings | frames | ms/frame | core ns/unit | indirect RMSE | indirect relMSE | ÷ {BASELINE} | indirect relMSE against the exact setting | indirect FLIP | full RMSE | full relMSE | full FLIP | full % similar | % similar to first | image |"
    );
    let _ = writeln!(
        out,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for r in &report.rows {
        let settings = if r.settings.is_empty() {
            "defaults".to_string()
        } else {
            r.settings
                .iter()
                .map(|(n, v)| format!("{n} {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let core = r.core.as_ref().map_or("-".to_string(), |c| {
            format!("{:.2} ({} per {})", c.ns_per_unit, c.pass, c.unit)
        });
        let ratio = r
            .rel_mse_vs_ambient
            .map_or("-".to_string(), |v| format!("{v:.3}"));
        let against_exact = r
            .vs_exact_setting
            .as_ref()
            .map_or("-".to_string(), |m| format!("{:.2e}", m.rel_mse));
        let _ = writeln!(
            out,
            "| {} | {settings} | {} | {:.2} | {core} | {:.5} | {:.5} | {ratio} | {against_exact} | {:.4} | {:.5} | {:.5} | {:.4} | {:.3} | {:.3} | [png]({}) |",
            r.method,
            r.frames,
            r.ms_per_frame,
            r.indirect.rmse,
            r.indirect.rel_mse,
            r.indirect.flip,
            r.full.rmse,
            r.full.rel_mse,
            r.full.flip,
            100.0 * r.full.similarity,
            100.0 * r.similarity_vs_first,
            r.image
        );
    }
    out
}

/// The methods of the report's rows, in order of first appearance.
fn row_methods(report: &Report) -> Vec<&'static str> {
    let mut methods: Vec<&'static str> = Vec::new();
    for r in &report.rows {
        if !methods.contains(&r.method) {
            methods.push(r.method);
        }
    }
    methods
}

fn write_plots(dir: &Path, report: &Report) -> anyhow::Result<()> {
    let all: Vec<(f64, f64)> = report
        .rows
        .iter()
        .map(|r| (r.ms_per_frame, r.indirect.rmse))
        .collect();
    let front = pareto_front(&all);
    let series = row_methods(report)
        .into_iter()
        .enumerate()
        .map(|(colour, method)| {
            let idx: Vec<usize> = (0..report.rows.len())
                .filter(|&i| report.rows[i].method == method)
                .collect();
            Series {
                label: method.to_string(),
                points: idx.iter().map(|&i| all[i]).collect(),
                marked: idx.iter().map(|&i| front[i]).collect(),
                connect: false,
                colour,
            }
        })
        .collect();
    let plot = Plot {
        title: format!(
            "{}: indirect RMSE against GPU ms per frame (ringed: Pareto front)",
            report.scene
        ),
        x_label: "ms per frame".into(),
        y_label: "indirect RMSE".into(),
        series,
    };
    write_png(&dir.join("error_vs_time.png"), &plot.render()?)?;

    let mut series = Vec::new();
    let mut units_name = "unit";
    for (colour, method) in row_methods(report).into_iter().enumerate() {
        let mut by_units: Vec<(usize, Vec<f64>)> = Vec::new();
        for core in report
            .rows
            .iter()
            .filter(|r| r.method == method)
            .filter_map(|r| r.core.as_ref())
            .filter(|c| c.ns_per_unit > 0.0)
        {
            units_name = core.unit;
            match by_units.iter_mut().find(|e| e.0 == core.units) {
                Some(e) => e.1.push(core.ns_per_unit),
                None => by_units.push((core.units, vec![core.ns_per_unit])),
            }
        }
        if by_units.is_empty() {
            continue;
        }
        by_units.sort_by_key(|e| e.0);
        series.push(Series {
            label: method.to_string(),
            points: by_units
                .into_iter()
                .map(|(units, v)| {
                    let median = crate::gpu::profiler::summarize("", v.len(), v).median_ns;
                    (units as f64, median)
                })
                .collect(),
            marked: Vec::new(),
            connect: true,
            colour,
        });
    }
    let plot = Plot {
        title: format!(
            "{}: core pass ns per {units_name} against problem size",
            report.scene
        ),
        x_label: format!("{units_name}s"),
        y_label: format!("ns per {units_name} per run"),
        series,
    };
    write_png(&dir.join("ns_per_unit.png"), &plot.render()?)
}

/// The reference, each method at its default settings, and their FLIP error maps, side by side.
fn write_strip(
    gpu: &Gpu,
    scene: &Scene,
    dir: &Path,
    (direct, truth): (&HdrImage, &ReferenceImages),
    frame: &mut Frame,
    methods: &[&MethodEntry],
) -> anyhow::Result<()> {
    let reference = truth.combined();
    let mut panels = vec![("reference".to_string(), tonemapped(&reference)?)];
    let mut maps = Vec::new();
    for entry in methods {
        let settings = entry.settings(&[])?;
        let frames = (entry.settle_frames)(&settings);
        let run = run_config(gpu, scene, frame, truth, (entry, &settings), frames)?;
        let full = add(direct, &run.indirect);
        panels.push((entry.name.to_string(), tonemapped(&full)?));
        let rgb: Vec<u8> = metrics::flip_heatmap(&full, &reference)
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let map =
            RgbImage::from_raw(reference.width, reference.height, rgb).context("FLIP map size")?;
        maps.push((format!("{} FLIP", entry.name), map));
    }
    panels.extend(maps);
    write_png(&dir.join("strip.png"), &strip(&panels)?)
}

/// `vkgi report`.
pub fn run_command(args: &ReportArgs) -> anyhow::Result<()> {
    if args.spp == 0 {
        crate::bad_input!("--spp must be at least 1");
    }
    let config = ReportConfig {
        scene: args.scene.clone(),
        out_dir: args.out_dir.clone(),
        size: args.size,
        spp: args.spp,
        methods: args.method.clone(),
        grid: args.grid.values.clone(),
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
    use crate::gi::registry;

    #[test]
    fn the_grid_is_every_combination_of_listed_and_swept_values() {
        for entry in registry::methods() {
            let swept: usize = entry
                .settings
                .iter()
                .map(|s| s.sweep.len().max(1))
                .product();
            let configs = match grid(entry, &[]) {
                Ok(c) => c,
                Err(e) => panic!("{e}"),
            };
            assert_eq!(configs.len(), swept, "{}", entry.name);
            let Some(setting) = entry.settings.first() else {
                continue;
            };
            let user = vec![(setting.name.to_string(), vec![setting.default.to_string()])];
            let configs = match grid(entry, &user) {
                Ok(c) => c,
                Err(e) => panic!("{e}"),
            };
            assert_eq!(
                configs.len(),
                swept / setting.sweep.len().max(1),
                "{}: one value given",
                entry.name
            );
        }
    }

    #[test]
    fn image_names_are_safe_file_names() {
        let name = image_name("m", &[("a b".into(), "0.5/1".into())]);
        assert_eq!(name, "images/m-a_b0.5_1.png");
    }
}
