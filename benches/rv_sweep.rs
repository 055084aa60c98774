//! Seed 001's sweeps (spec 001 §6) regenerated for `radiance-volumes` (issue #16, item 6):
//! caches held, GPU memory and per-pass time against screen resolution, cascade count, voxel
//! resolution and shadow LOD (on the Cornell box and `atrium`) and the specular map's side (on
//! their glossy variants), each configuration otherwise at the method's defaults, indirect
//! light only.
//!
//! cargo bench --bench rv_sweep [-- OUT_DIR]   (the markdown table to stdout, as
//! docs/radiance-volumes.md holds it; one plot per sweep, rv-sweep-*.png, in OUT_DIR,
//! docs/images by default)

mod common;

use vkgi::gi::radiance_volumes::RadianceVolumes;
use vkgi::gi::registry::{self, Setup};
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::metrics::plot::{Series, write_plot};
use vkgi::render::runner::run_frames;
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

/// Frames run before the measured ones (the defaults settle in 4; the counters arrive a frame
/// late), and frames measured.
const WARMUP: u32 = 4;
const MEASURED: u32 = 3;

/// The passes the table lists, by name.
const PASSES: [&str; 3] = ["rv allocate", "rv light", "rv apply"];

/// One measured configuration.
struct Point {
    caches: u32,
    memory_mib: f64,
    /// Median ms of each of [`PASSES`], then of the frame.
    ms: [f64; 4],
}

fn measure(
    gpu: &Gpu,
    scene: &Scene,
    size: (u32, u32),
    settings: &[(&str, String)],
) -> anyhow::Result<Point> {
    let entry = registry::lookup("radiance-volumes")?.expect("radiance-volumes is registered");
    let overrides: Vec<(String, String)> = settings
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    let mut rv = RadianceVolumes::new(&Setup::new(gpu, scene), &entry.settings(&overrides)?)?;
    let options = FrameOptions {
        width: size.0,
        height: size.1,
        indirect_only: true,
        ..FrameOptions::default()
    };
    let mut frame = Frame::new(gpu, scene, options)?;
    let ring = run_frames(gpu, &mut frame, Some(&mut rv), WARMUP, MEASURED)?;
    let report = ring.profiler.report();
    let median = |name: &str| {
        report
            .passes
            .iter()
            .filter(|p| p.name == name)
            .map(|p| p.median_ns)
            .sum::<f64>()
            / 1e6
    };
    let frame_ms = report
        .frame
        .as_ref()
        .map_or(f64::NAN, |f| f.median_ns / 1e6);
    let memory: u64 = rv.passes.memory().iter().map(|(_, bytes)| bytes).sum();
    Ok(Point {
        caches: rv.state().held(rv.settings.capacity),
        memory_mib: memory as f64 / f64::from(1u32 << 20),
        ms: [
            median(PASSES[0]),
            median(PASSES[1]),
            median(PASSES[2]),
            frame_ms,
        ],
    })
}

/// One point of a sweep: its x value, the image size and the settings that differ from the
/// defaults.
type SweepPoint = (f64, (u32, u32), Vec<(&'static str, String)>);

/// A sweep: its name, the x axis's label, the scenes it runs on, and its points.
struct Sweep {
    name: &'static str,
    axis: &'static str,
    scenes: [&'static str; 2],
    points: Vec<SweepPoint>,
}

/// The scenes of the sweeps that need no glossy material.
const SCENES: [&str; 2] = ["cornell", "atrium"];

fn sweeps() -> Vec<Sweep> {
    let small = (160, 120);
    vec![
        Sweep {
            name: "screen",
            axis: "pixels",
            scenes: SCENES,
            points: [(160, 120), (320, 240), (640, 480)]
                .map(|(w, h)| (f64::from(w * h), (w, h), vec![]))
                .to_vec(),
        },
        Sweep {
            name: "cascades",
            axis: "cascades",
            scenes: SCENES,
            points: (1..=4)
                .map(|c| (f64::from(c), small, vec![("cascades", c.to_string())]))
                .collect(),
        },
        Sweep {
            name: "voxels",
            axis: "voxels per side",
            scenes: SCENES,
            points: [32, 64, 128, 256]
                .map(|v| (f64::from(v), small, vec![("voxels", v.to_string())]))
                .to_vec(),
        },
        Sweep {
            name: "shadow-lod",
            axis: "shadow LOD + 1 (one cone per 4^LOD VALs)",
            scenes: SCENES,
            points: (0..=3)
                .map(|l| (f64::from(l + 1), small, vec![("shadow-lod", l.to_string())]))
                .collect(),
        },
        Sweep {
            name: "specular",
            axis: "specular map side",
            scenes: ["cornell-glossy", "atrium-glossy"],
            points: [4, 8, 16]
                .map(|p| (f64::from(p), small, vec![("specular", p.to_string())]))
                .to_vec(),
        },
    ]
}

fn main() -> anyhow::Result<()> {
    let out = common::out_dir()?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    println!(
        "| scene | sweep | value | caches | memory MiB | {} ms | frame ms |",
        PASSES.join(" ms | ")
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut plots: Vec<(&str, &str, Vec<Series>)> = Vec::new();
    for sweep in sweeps() {
        let mut series = Vec::new();
        for (colour, name) in sweep.scenes.iter().enumerate() {
            let scene = Scene::load(name)?;
            let mut caches = Vec::new();
            let mut memory = Vec::new();
            let mut light = Vec::new();
            let mut apply = Vec::new();
            for (x, size, settings) in &sweep.points {
                let p = measure(&gpu, &scene, *size, settings)?;
                let value = match sweep.name {
                    "screen" => format!("{}x{}", size.0, size.1),
                    "shadow-lod" => format!("{}", x - 1.0),
                    _ => format!("{x}"),
                };
                println!(
                    "| {name} | {} | {value} | {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |",
                    sweep.name, p.caches, p.memory_mib, p.ms[0], p.ms[1], p.ms[2], p.ms[3]
                );
                caches.push((*x, f64::from(p.caches)));
                memory.push((*x, p.memory_mib));
                light.push((*x, p.ms[1]));
                apply.push((*x, p.ms[2]));
            }
            series.push(Series::line(&format!("{name}: caches"), colour, caches));
            series.push(Series::line(
                &format!("{name}: memory MiB"),
                colour + 2,
                memory,
            ));
            series.push(Series::line(
                &format!("{name}: rv light ms"),
                colour + 4,
                light,
            ));
            if sweep.name == "specular" {
                series.push(Series::line(
                    &format!("{name}: rv apply ms"),
                    colour + 6,
                    apply,
                ));
            }
        }
        plots.push((sweep.name, sweep.axis, series));
    }
    for (name, axis, series) in plots {
        let path = out.join(format!("rv-sweep-{name}.png"));
        write_plot(
            &path,
            &format!("radiance-volumes: caches, memory and pass times against {axis}"),
            axis,
            "caches / MiB / ms",
            series,
        )?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
