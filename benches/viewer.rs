//! The viewer's frame rate (issue 18 item 3): `vkgi view` with ILPV at its defaults on a
//! virtual display (Xvfb, started here), one 800x600 view and the CAVE's four 320x320 walls, no
//! vsync, and the one view again with its light treated as moving in every frame. Each configuration runs for a short and a long count of frames, three times each; the
//! frame rate is the extra frames over the extra median wall time, so window set-up and the GI
//! method's build cancel out.
//!
//! cargo bench --bench viewer [-- SHORT LONG], e.g. `-- 5 45`

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::Instant;

/// Kills the X server when the bench ends, however it ends.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn main() -> anyhow::Result<()> {
    let args: Vec<u64> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let (short, long) = (
        args.first().copied().unwrap_or(5),
        args.get(1).copied().unwrap_or(45),
    );
    anyhow::ensure!(short >= 1 && long > short, "0 < SHORT < LONG frames");
    // -displayfd 1: Xvfb picks a free display and prints its number once it is ready.
    let mut child = Command::new("Xvfb")
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "1280x1024x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()?;
    let stdout = child
        .stdout
        .take()
        .ok_or_else(|| anyhow::anyhow!("no stdout"))?;
    let server = Server(child);
    let mut number = String::new();
    BufReader::new(stdout).read_line(&mut number)?;
    let display = format!(":{}", number.trim());
    // The scene and its light stand still, so frames keep the shadow maps, RSM and injection;
    // the last row redoes them every frame, as a moving light does (no target of its own).
    let configurations: [(&str, &[&str], &str); 3] = [
        ("one view, 800x600", &["--size", "800x600"], "12"),
        (
            "CAVE, four 320x320 walls",
            &["--cave", "--size", "960x640"],
            "10",
        ),
        (
            "one view, 800x600, the light moving",
            &["--size", "800x600", "--lights-move"],
            "-",
        ),
    ];
    println!("ILPV defaults, cornell, no vsync, on {display}");
    println!("configuration | frames per second | target");
    println!("---|---|---");
    for (name, extra, target) in configurations {
        let seconds = |frames: u64| -> anyhow::Result<f64> {
            let mut runs = Vec::new();
            for _ in 0..3 {
                let start = Instant::now();
                let status = Command::new(env!("CARGO_BIN_EXE_vkgi"))
                    .args(["view", "--scene", "cornell", "--no-vsync", "--frames"])
                    .arg(frames.to_string())
                    .args(extra)
                    .env("DISPLAY", &display)
                    .stdout(Stdio::null())
                    .status()?;
                anyhow::ensure!(status.success(), "vkgi view failed ({name})");
                runs.push(start.elapsed().as_secs_f64());
            }
            runs.sort_by(f64::total_cmp);
            Ok(runs[1])
        };
        let fps = (long - short) as f64 / (seconds(long)? - seconds(short)?);
        println!("{name} | {fps:.1} | {target}");
    }
    drop(server);
    Ok(())
}
