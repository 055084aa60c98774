//! The CAVE's frame lock on loopback (issue 17, docs/view.md): a `vkgi cave-master` and N
//! `vkgi cave-node`s (ILPV, fixed-point injection, 48x48 walls, no validation) run a scripted
//! head and light; the master's report gives per frame the parameter-sync latency (sending the
//! frame's updates to the last node's acknowledgement) and the frame-lock wait (the longest any
//! node waited, after finishing a frame, for the next). Medians and 95th percentiles over the
//! frames after the first (whose sync includes the nodes' pipeline warm-up).
//!
//! cargo bench --bench cave_sync [-- NODES FRAMES], e.g. `-- 2,4,8 60`

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

const WALLS: [&str; 6] = ["front", "left", "right", "floor", "back", "ceiling"];
/// Nodes per wall: one per eye, as a stereo CAVE with a projector per eye runs.
const EYES: [&str; 2] = ["left", "right"];

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let counts: Vec<usize> = match args.first() {
        Some(list) => list.split(',').map(str::parse).collect::<Result<_, _>>()?,
        None => vec![2, 4, 8],
    };
    let frames: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(60);
    anyhow::ensure!(
        counts.iter().all(|&c| (1..=12).contains(&c)) && frames >= 2,
        "1 to 12 nodes (6 walls, 2 eyes each) and at least 2 frames"
    );
    let dir = std::env::temp_dir().join(format!("vkgi-cave-sync-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let path = dir.join("path.txt");
    let samples: String = (0..frames)
        .map(|f| {
            let t = f as f32 / frames as f32;
            format!("{:.4} 0.1 0.3 {:.4} 0.54 0.27\n", 0.3 * t, 0.25 + 0.1 * t)
        })
        .collect();
    std::fs::write(&path, samples)?;
    println!(
        "nodes | sync median ms | sync p95 ms | lock wait median ms | lock wait p95 ms | slowest render median ms"
    );
    println!("---|---|---|---|---|---");
    for &count in &counts {
        let report = dir.join(format!("report-{count}.json"));
        let mut master = spawn(&[
            "cave-master",
            "--listen",
            "127.0.0.1:0",
            "--nodes",
            &count.to_string(),
            "--frames",
            &frames.to_string(),
            "--path",
            path.to_str().unwrap_or_default(),
            "--report",
            report.to_str().unwrap_or_default(),
            "--node-timeout",
            "120",
        ])?;
        let stdout = master
            .stdout
            .take()
            .ok_or_else(|| anyhow::anyhow!("no stdout"))?;
        let mut lines = BufReader::new(stdout).lines();
        let first = lines.next().transpose()?.unwrap_or_default();
        let address = first
            .split_whitespace()
            .nth(3)
            .ok_or_else(|| anyhow::anyhow!("the master said '{first}'"))?
            .to_string();
        let mut nodes = Vec::new();
        for i in 0..count {
            let (wall, eye) = (WALLS[i / 2], EYES[i % 2]);
            nodes.push(spawn(&[
                "cave-node",
                "--headless",
                "--master",
                &address,
                "--wall",
                wall,
                "--eye",
                eye,
                "--size",
                "48x48",
            ])?);
        }
        for line in lines.map_while(Result::ok) {
            if line.contains("refused") || line.contains("lost the") {
                eprintln!("{line}");
            }
        }
        let status = master.wait()?;
        for mut node in nodes {
            node.wait()?;
        }
        anyhow::ensure!(status.success(), "the master failed with {count} nodes");
        let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report)?)?;
        let column = |key: &str| -> Vec<f64> {
            json["frames"]
                .as_array()
                .map(|f| f.iter().skip(1).filter_map(|r| r[key].as_f64()).collect())
                .unwrap_or_default()
        };
        let (sync, wait, render) = (
            column("sync_ms"),
            column("lock_wait_ms"),
            column("render_ms"),
        );
        println!(
            "{count} | {:.3} | {:.3} | {:.3} | {:.3} | {:.1}",
            percentile(&sync, 0.5),
            percentile(&sync, 0.95),
            percentile(&wait, 0.5),
            percentile(&wait, 0.95),
            percentile(&render, 0.5)
        );
    }
    Ok(())
}

fn spawn(args: &[&str]) -> anyhow::Result<Child> {
    Ok(Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(args)
        .stdout(if args[0] == "cave-master" {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .spawn()?)
}

fn percentile(values: &[f64], q: f64) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let index = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted.get(index).copied().unwrap_or(f64::NAN)
}
