//! Set-up cost against scene size: a height-field OBJ of N triangles (default 2 000 000) is
//! written to a temporary folder, then loaded, uploaded (the frame) and given ILPV's set-up
//! (transfer vectors, geometry lattice, GPU resources), each timed by wall clock, with the
//! process's resident memory after each step and its peak, against the OBJ's size.
//!
//! cargo bench --bench scale [-- TRIANGLES]

use std::io::Write;
use std::time::Instant;

use vkgi::gi::lpv::{Lpv, LpvSettings};
use vkgi::gi::registry::Setup;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

/// Resident and peak resident memory of this process, MiB (Linux /proc).
fn memory_mib() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .map_or(0.0, |kib| kib / 1024.0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// Write a wavy height field of about `triangles` triangles; returns its path.
fn write_obj(dir: &std::path::Path, triangles: usize) -> anyhow::Result<std::path::PathBuf> {
    let side = ((triangles as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let path = dir.join(format!("field-{triangles}.obj"));
    let mut out = std::io::BufWriter::new(std::fs::File::create(&path)?);
    for z in 0..=side {
        for x in 0..=side {
            let (u, v) = (x as f64 / side as f64, z as f64 / side as f64);
            let y = 0.05 * ((u * 40.0).sin() + (v * 30.0).cos());
            writeln!(out, "v {u:.6} {y:.6} {v:.6}")?;
        }
    }
    let index = |x: usize, z: usize| z * (side + 1) + x + 1;
    for z in 0..side {
        for x in 0..side {
            let (a, b, c, d) = (
                index(x, z),
                index(x + 1, z),
                index(x + 1, z + 1),
                index(x, z + 1),
            );
            writeln!(out, "f {a} {b} {c}\nf {a} {c} {d}")?;
        }
    }
    out.flush()?;
    Ok(path)
}

fn main() -> anyhow::Result<()> {
    let triangles: usize = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with("--"))
        .map(|a| a.parse())
        .transpose()?
        .unwrap_or(2_000_000);
    let dir = std::env::temp_dir().join(format!("vkgi-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let path = write_obj(&dir, triangles)?;
    let obj_mib = std::fs::metadata(&path)?.len() as f64 / (1 << 20) as f64;
    let gpu = Gpu::new(&GpuOptions::default())?;
    let (base, _) = memory_mib();
    println!(
        "OBJ of {triangles} triangles: {obj_mib:.1} MiB; process before loading: {base:.0} MiB"
    );

    let start = Instant::now();
    let scene = Scene::load(path.to_str().unwrap_or_default())?;
    let load_s = start.elapsed().as_secs_f64();
    let (rss, peak) = memory_mib();
    println!(
        "load:        {load_s:7.2} s  resident {rss:6.0} MiB  peak {peak:6.0} MiB ({} triangles)",
        scene.mesh.triangle_count()
    );

    let start = Instant::now();
    let frame = Frame::new(
        &gpu,
        &scene,
        FrameOptions {
            width: 320,
            height: 240,
            ..FrameOptions::default()
        },
    )?;
    let frame_s = start.elapsed().as_secs_f64();
    let (rss, peak) = memory_mib();
    println!(
        "frame:       {frame_s:7.2} s  resident {rss:6.0} MiB  peak {peak:6.0} MiB (scene buffers uploaded)"
    );

    let start = Instant::now();
    let lpv = Lpv::new(&Setup::new(&gpu, &scene), LpvSettings::default())?;
    let lpv_s = start.elapsed().as_secs_f64();
    let (rss, peak) = memory_mib();
    println!("ilpv set-up: {lpv_s:7.2} s  resident {rss:6.0} MiB  peak {peak:6.0} MiB");
    println!(
        "ilpv set-up / (load + frame) = {:.2}; ilpv set-up per triangle {:.0} ns; peak / OBJ size = {:.1}",
        lpv_s / (load_s + frame_s),
        lpv_s / triangles as f64 * 1e9,
        (peak - base) / obj_mib
    );
    drop((lpv, frame));
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
