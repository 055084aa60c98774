//! The CAVE over several processes (issue 17, spec 000 §11): a `vkgi cave-master` and
//! `vkgi cave-node`s on loopback, validation on in every node. Every wait has a deadline and
//! every child is killed if a test fails, so nothing hangs the suite.

use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

mod common;

/// Longest any process of a test may take.
const DEADLINE: Duration = Duration::from_secs(300);

/// A child process whose stdout lines arrive on a channel; killed when dropped.
struct Process {
    child: Child,
    lines: Receiver<String>,
    seen: Vec<String>,
    /// Everything the child wrote to stderr, read as it comes (a full pipe would block it).
    stderr: Option<std::thread::JoinHandle<String>>,
}

impl Process {
    fn start(args: &[&str]) -> Process {
        Process::spawn(Command::new(env!("CARGO_BIN_EXE_vkgi")).args(args))
    }

    fn spawn(command: &mut Command) -> Process {
        let mut child = command
            .env("VKGI_VALIDATE", "1")
            .env("RUST_BACKTRACE", "0")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the program runs");
        let (send, lines) = channel();
        let stdout = child.stdout.take().unwrap();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        let mut pipe = child.stderr.take().unwrap();
        let stderr = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = std::io::Read::read_to_string(&mut pipe, &mut text);
            text
        });
        Process {
            child,
            lines,
            seen: Vec::new(),
            stderr: Some(stderr),
        }
    }

    /// The first stdout line containing `needle` (waiting at most the deadline).
    fn wait_for(&mut self, needle: &str) -> String {
        let end = Instant::now() + DEADLINE;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.seen.push(line.clone());
                    if line.contains(needle) {
                        return line;
                    }
                }
                Err(_) => panic!("no line with '{needle}'; saw {:#?}", self.seen),
            }
        }
    }

    /// Wait for the exit: (code, every stdout line, stderr).
    fn finish(mut self) -> (Option<i32>, Vec<String>, String) {
        let end = Instant::now() + DEADLINE;
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            assert!(Instant::now() < end, "still running after {DEADLINE:?}");
            std::thread::sleep(Duration::from_millis(20));
        };
        let stderr = self
            .stderr
            .take()
            .map(|reader| reader.join().unwrap_or_default())
            .unwrap_or_default();
        let mut lines = std::mem::take(&mut self.seen);
        while let Ok(line) = self.lines.recv_timeout(Duration::from_secs(5)) {
            lines.push(line);
        }
        (status.code(), lines, stderr)
    }

    fn signal(&self, signal: &str) {
        let status = Command::new("kill")
            .args([signal, &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A master on a free loopback port; its address.
fn master(args: &[&str]) -> (Process, String) {
    let mut all = vec!["cave-master", "--listen", "127.0.0.1:0"];
    all.extend_from_slice(args);
    let mut master = Process::start(&all);
    let line = master.wait_for("listening on");
    let address = line
        .split_whitespace()
        .nth(3)
        .expect("listening on ADDRESS")
        .to_string();
    (master, address)
}

/// A headless node.
fn node(address: &str, wall: &str, prefix: &Path, extra: &[&str]) -> Process {
    let mut args = vec!["--headless"];
    args.extend_from_slice(extra);
    let args = node_args(address, wall, prefix, &args);
    Process::start(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// A node with a window on X display `display`.
fn windowed_node(address: &str, wall: &str, prefix: &Path, display: &str) -> Process {
    let args = node_args(address, wall, prefix, &[]);
    Process::spawn(
        Command::new(env!("CARGO_BIN_EXE_vkgi"))
            .args(&args)
            .env("DISPLAY", display),
    )
}

fn node_args(address: &str, wall: &str, prefix: &Path, extra: &[&str]) -> Vec<String> {
    let prefix = prefix.to_string_lossy().into_owned();
    let mut args = vec![
        "cave-node",
        "--master",
        address,
        "--wall",
        wall,
        "--screenshot",
        &prefix,
    ];
    if !extra.contains(&"--size") {
        args.extend(["--size", "48x48"]);
    }
    args.extend_from_slice(extra);
    args.into_iter().map(String::from).collect()
}

/// A node ran to the end: exit 0, no validation message.
fn assert_clean(name: &str, (code, lines, stderr): &(Option<i32>, Vec<String>, String)) {
    assert_eq!(*code, Some(0), "{name}: {lines:#?}\n{stderr}");
    assert!(!stderr.contains("validation:"), "{name}: {stderr}");
}

/// Head and light samples: the head sways right and up, the spot light slides along x.
fn path_file(dir: &Path, frames: usize) -> PathBuf {
    let text: String = (0..frames)
        .map(|f| {
            let t = f as f32 / frames as f32;
            format!(
                "{:.4} {:.4} 0.3 {:.4} 0.54 0.27\n",
                0.1 + 0.3 * t,
                0.1 - 0.2 * t,
                0.25 + 0.1 * t
            )
        })
        .collect();
    let path = dir.join("path.txt");
    std::fs::write(&path, text).unwrap();
    path
}

fn report(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// Every frame's lattice digests: one per node, all equal and present.
fn assert_lattices_agree(report: &serde_json::Value, nodes: usize, frames: usize) {
    let records = report["frames"].as_array().unwrap();
    assert!(records.len() >= frames);
    for record in &records[..frames] {
        let digests: Vec<&str> = record["lattices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|pair| pair[1].as_str().expect("a lattice digest"))
            .collect();
        assert_eq!(digests.len(), nodes, "{record}");
        assert!(digests.iter().all(|d| *d == digests[0]), "{record}");
    }
}

fn hdr(path: &Path) -> Vec<u32> {
    let image = vkgi::imageio::read_hdr(path, false).unwrap();
    image.pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

/// A virtual X server (Xvfb, as xvfb-run starts it) on a free display, stopped when dropped.
struct VirtualDisplay {
    server: Process,
    name: String,
}

impl VirtualDisplay {
    fn start() -> VirtualDisplay {
        // -displayfd 1: Xvfb picks a free display and prints its number once it is ready.
        let mut server = Process::spawn(Command::new("Xvfb").args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "1024x768x24",
            "-nolisten",
            "tcp",
        ]));
        let number = server.wait_for("");
        VirtualDisplay {
            name: format!(":{}", number.trim()),
            server,
        }
    }
}

#[test]
fn four_nodes_render_the_single_process_cave_tiles_bit_for_bit() {
    let x = VirtualDisplay::start();
    let dir = common::cli::scratch("cave", "four");
    let frames = 30;
    let path = path_file(&dir, frames);
    let report_path = dir.join("report.json");
    let (master, address) = master(&[
        "--nodes",
        "4",
        "--frames",
        "30",
        "--path",
        path.to_str().unwrap(),
        "--report",
        report_path.to_str().unwrap(),
    ]);
    let walls = ["front", "left", "right", "floor"];
    // Each node in its own window, on the one virtual display.
    let nodes: Vec<Process> = walls
        .iter()
        .map(|wall| windowed_node(&address, wall, &dir.join("node"), &x.name))
        .collect();
    let summary = master.finish();
    assert_clean("master", &summary);
    assert!(
        summary
            .1
            .iter()
            .any(|l| l.contains("lattices bit-identical")),
        "{:#?}",
        summary.1
    );
    for (wall, node) in walls.iter().zip(nodes) {
        assert_clean(wall, &node.finish());
    }
    assert_lattices_agree(&report(&report_path), 4, frames);

    // The same frames from one process: the walls tiled 3x2 in one 144x96 window (48x48 each).
    let output = Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(["view", "--cave", "--size", "144x96", "--frames", "30"])
        .args(["--path", path.to_str().unwrap(), "--injection", "fixed"])
        .arg("--screenshot")
        .arg(dir.join("single"))
        .env("VKGI_VALIDATE", "1")
        .env("DISPLAY", &x.name)
        .output()
        .expect("vkgi runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("validation:"), "{stderr}");
    for wall in walls {
        let single = hdr(&dir.join(format!("single-{wall}.exr")));
        let node = hdr(&dir.join(format!("node-{wall}.exr")));
        assert_eq!(single.len(), 48 * 48 * 3, "{wall}");
        assert!(single.iter().any(|&bits| bits != 0), "{wall} is lit");
        assert!(
            single == node,
            "{wall}: the node's wall differs from the tile"
        );
        // The node's window shows the wall under its overlay.
        let window = image::open(dir.join(format!("node-{wall}-window.png"))).unwrap();
        assert_eq!((window.width(), window.height()), (48, 48), "{wall}");
    }
    drop(x.server);
}

/// Spec 000 §11.4 and issue 17 item 3: three nodes carry bit-identical lattices on every frame,
/// and with --edge-pixels (the outer pixel centres on the wall edges) the indirect light two
/// walls draw along their shared edge agrees to float rounding of the rasterised positions.
#[test]
fn three_nodes_agree_on_their_lattices_and_along_their_shared_edges() {
    let dir = common::cli::scratch("cave", "seams");
    let report_path = dir.join("report.json");
    let (master, address) = master(&[
        "--nodes",
        "3",
        "--frames",
        "12",
        "--edge-pixels",
        "--indirect-only",
        "--report",
        report_path.to_str().unwrap(),
    ]);
    let walls = ["left", "front", "right"];
    let nodes: Vec<Process> = walls
        .iter()
        .map(|wall| node(&address, wall, &dir.join("node"), &[]))
        .collect();
    assert_clean("master", &master.finish());
    for (wall, node) in walls.iter().zip(nodes) {
        assert_clean(wall, &node.finish());
    }
    assert_lattices_agree(&report(&report_path), 3, 12);
    let image =
        |wall: &str| vkgi::imageio::read_hdr(&dir.join(format!("node-{wall}.exr")), false).unwrap();
    let (left, front, right) = (image("left"), image("front"), image("right"));
    let n = front.width;
    let column = |image: &vkgi::imageio::HdrImage, x: u32| -> Vec<[f32; 3]> {
        (0..n).map(|y| image.at(x, y)).collect()
    };
    // Summed |a - b| over the summed mean, every channel of every pixel along the edge.
    let difference = |a: Vec<[f32; 3]>, b: Vec<[f32; 3]>| {
        let pairs = a.iter().flatten().zip(b.iter().flatten());
        let (diff, mean) = pairs.fold((0.0, 0.0), |(d, m), (x, y)| {
            (d + f64::from((x - y).abs()), m + 0.5 * f64::from(x + y))
        });
        assert!(mean > 0.0, "the edge is lit");
        diff / mean
    };
    let front_right = difference(column(&front, n - 1), column(&right, 0));
    let left_front = difference(column(&left, n - 1), column(&front, 0));
    let apart = difference(column(&front, 0), column(&front, n - 1));
    println!(
        "shared edges: front|right {front_right:.2e}, left|front {left_front:.2e}; apart {apart:.2}"
    );
    assert!(
        front_right < 1e-6 && left_front < 1e-6,
        "{front_right} {left_front}"
    );
    assert!(apart > 0.1, "edges that do not meet differ: {apart}");
}

#[test]
fn a_killed_node_is_named_and_the_others_finish_with_identical_lattices() {
    let dir = common::cli::scratch("cave", "killed");
    let report_path = dir.join("report.json");
    let (mut master, address) = master(&[
        "--nodes",
        "3",
        "--frames",
        "20",
        "--log-frames",
        "--node-timeout",
        "20",
        "--report",
        report_path.to_str().unwrap(),
    ]);
    let front = node(&address, "front", &dir.join("node"), &[]);
    let left = node(&address, "left", &dir.join("node"), &[]);
    let right = node(&address, "right", &dir.join("node"), &[]);
    master.wait_for("cave-master: frame 5 ");
    right.signal("-KILL");
    let lost = master.wait_for("lost the");
    assert!(
        lost.contains("lost the right wall") && lost.contains("connection closed"),
        "{lost}"
    );
    let summary = master.finish();
    assert_clean("master", &summary);
    assert!(
        summary
            .1
            .iter()
            .any(|l| l.contains("20 frames on 2 node(s) (1 lost)")),
        "{:#?}",
        summary.1
    );
    assert_clean("front", &front.finish());
    assert_clean("left", &left.finish());
    let report = report(&report_path);
    // Three nodes agree on every frame before the loss, two on every frame after it.
    let frames = report["frames"].as_array().unwrap();
    let lost_at = frames
        .iter()
        .position(|f| f["lattices"].as_array().unwrap().len() < 3)
        .expect("a frame without the right wall");
    assert!((6..20).contains(&lost_at), "lost at frame {lost_at}");
    assert_lattices_agree(&report, 3, lost_at);
    let after = frames[lost_at + 1..].to_vec();
    assert_lattices_agree(&serde_json::json!({ "frames": after }), 2, 19 - lost_at);
    assert!(dir.join("node-front.exr").is_file() && !dir.join("node-right.exr").exists());
}

#[test]
fn nodes_wait_for_the_master_foreign_nodes_are_refused_and_a_silent_node_times_out() {
    let dir = common::cli::scratch("cave", "faults");
    // A free port the master will take after the first node started.
    let address = {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        listener.local_addr().unwrap().to_string()
    };
    let mut early = node(&address, "front", &dir.join("node"), &[]);
    early.wait_for("waiting for the master");
    let mut master = Process::start(&[
        "cave-master",
        "--listen",
        &address,
        "--nodes",
        "2",
        "--frames",
        "60",
        "--log-frames",
        "--node-timeout",
        "5",
    ]);
    master.wait_for("the front wall joined");

    // Another scene: refused in one line on both ends, exit 2; the master goes on waiting.
    let foreign = node(
        &address,
        "left",
        &dir.join("foreign"),
        &["--scene", "two-rooms"],
    );
    let refused = foreign.finish();
    assert_eq!(refused.0, Some(2), "{refused:?}");
    assert!(
        refused
            .2
            .contains("refused by the master: its scene 'two-rooms'"),
        "{}",
        refused.2
    );
    master.wait_for("refused the left wall");

    // A node that stops answering (SIGSTOP) is lost after --node-timeout; the other goes on.
    let silent = node(&address, "left", &dir.join("node"), &[]);
    master.wait_for("cave-master: frame 3 ");
    silent.signal("-STOP");
    let lost = master.wait_for("lost the");
    assert!(
        lost.contains("lost the left wall") && lost.contains("stopped answering"),
        "{lost}"
    );
    silent.signal("-KILL");
    let summary = master.finish();
    assert_clean("master", &summary);
    assert_clean("front", &early.finish());
}

#[test]
fn both_eyes_from_one_frame_pass_equal_one_node_per_eye_and_lay_out_for_viewing() {
    let dir = common::cli::scratch("cave", "stereo");
    let path = path_file(&dir, 6);
    let run = |nodes: &[(&str, &[&str])], prefix: &str| {
        let (master, address) = master(&[
            "--nodes",
            &nodes.len().to_string(),
            "--frames",
            "6",
            "--path",
            path.to_str().unwrap(),
        ]);
        let nodes: Vec<Process> = nodes
            .iter()
            .map(|(wall, extra)| node(&address, wall, &dir.join(prefix), extra))
            .collect();
        (master, nodes)
    };
    let one_pass = run(
        &[(
            "front",
            &["--eye", "both", "--stereo", "top-bottom", "--size", "48x96"],
        )],
        "pass",
    );
    let per_eye = run(
        &[
            ("front", &["--eye", "left"]),
            ("front", &["--eye", "right"]),
        ],
        "eye",
    );
    for (master, nodes) in [one_pass, per_eye] {
        assert_clean("master", &master.finish());
        for node in nodes {
            assert_clean("node", &node.finish());
        }
    }
    for eye in ["left", "right"] {
        let pass = hdr(&dir.join(format!("pass-front-{eye}.exr")));
        let alone = hdr(&dir.join(format!("eye-front-{eye}.exr")));
        assert!(
            pass == alone,
            "{eye} eye: one frame pass differs from its own node"
        );
    }
    let (left, right) = (
        hdr(&dir.join("pass-front-left.exr")),
        hdr(&dir.join("pass-front-right.exr")),
    );
    assert!(left != right, "the eyes see from different places");
    let stereo = image::open(dir.join("pass-front-stereo.png")).unwrap();
    assert_eq!((stereo.width(), stereo.height()), (48, 96));
}

#[test]
fn the_masters_window_shows_the_sync_and_its_keys_send_new_versions() {
    let x = VirtualDisplay::start();
    let dir = common::cli::scratch("cave", "console");
    let report_path = dir.join("report.json");
    let prefix = dir.join("master");
    let mut all = vec!["cave-master", "--listen", "127.0.0.1:0", "--nodes", "1"];
    all.extend([
        "--frames",
        "8",
        "--window",
        "--keys",
        "right,right,d,pageup",
    ]);
    all.extend(["--report", report_path.to_str().unwrap()]);
    all.extend(["--screenshot", prefix.to_str().unwrap()]);
    let mut master = Process::spawn(
        Command::new(env!("CARGO_BIN_EXE_vkgi"))
            .args(&all)
            .env("DISPLAY", &x.name),
    );
    let address = master
        .wait_for("listening on")
        .split_whitespace()
        .nth(3)
        .unwrap()
        .to_string();
    let node = node(&address, "front", &dir.join("node"), &[]);
    assert_clean("master", &master.finish());
    assert_clean("node", &node.finish());
    // Frame 0 sends the head and the moved light (version 1); frames 1-3 are keyed (a
    // version each); then nothing changes.
    let versions: Vec<u64> = report(&report_path)["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["version"].as_u64().unwrap())
        .collect();
    assert_eq!(versions, [1, 2, 3, 4, 4, 4, 4, 4]);
    let window = image::open(dir.join("master-window.png"))
        .unwrap()
        .to_rgba8();
    let text = window.pixels().filter(|p| p[0] > 200 && p[1] > 200).count();
    assert!(text > 500, "the overlay's text: {text} white pixels");
    drop(x.server);
}

/// A node of another build is refused in one line (a raw client speaks the protocol), and
/// with --on-loss stop the master stops the others cleanly when one is lost.
#[test]
fn another_build_is_refused_and_on_loss_stop_stops_every_node() {
    use vkgi::cave::protocol::{Link, MasterMessage, NodeMessage};
    use vkgi::view::cave::EyeChoice;
    let dir = common::cli::scratch("cave", "stop");
    let (mut master, address) = master(&[
        "--nodes",
        "2",
        "--frames",
        "200",
        "--log-frames",
        "--on-loss",
        "stop",
    ]);
    let mut old = Link::new(std::net::TcpStream::connect(&address).unwrap()).unwrap();
    old.send(&NodeMessage::Hello {
        build: "vkgi 0.0.1 protocol 0".into(),
        wall: "back".into(),
        eye: EyeChoice::Mono,
        scene: "0".into(),
        scene_name: "cornell".into(),
    })
    .unwrap();
    match old.receive::<MasterMessage>(DEADLINE).unwrap() {
        MasterMessage::Refused { reason } => {
            assert!(
                reason.contains("its build is 'vkgi 0.0.1 protocol 0'"),
                "{reason}"
            )
        }
        other => panic!("{other:?}"),
    }
    // Something that is not a hello at all is refused too.
    let mut stranger = Link::new(std::net::TcpStream::connect(&address).unwrap()).unwrap();
    stranger.send(&"GET / HTTP/1.1").unwrap();
    match stranger.receive::<MasterMessage>(DEADLINE).unwrap() {
        MasterMessage::Refused { reason } => {
            assert!(reason.contains("its hello is not one of vkgi"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    let front = node(&address, "front", &dir.join("node"), &[]);
    let floor = node(&address, "floor", &dir.join("node"), &[]);
    master.wait_for("cave-master: frame 3 ");
    floor.signal("-KILL");
    master.wait_for("lost the floor wall");
    let (code, _, stderr) = master.finish();
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("stopped after losing the floor wall"),
        "{stderr}"
    );
    let (code, lines, stderr) = front.finish();
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        lines.iter().any(|l| l.contains("a wall was lost")),
        "{lines:?}"
    );
}

#[test]
fn bad_master_and_node_input_is_refused_with_one_line() {
    let dir = common::cli::scratch("cave", "input");
    let bad_path = common::cli::write(&dir, "bad.txt", "0 0 0\n0 0 nan\n");
    // A node that is to open a window needs a display; it says so before joining anything.
    let output = Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(["cave-node", "--wall", "front", "--connect-timeout", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("needs a display") && stderr.lines().count() == 1,
        "{stderr}"
    );
    for (args, needle) in [
        (
            vec!["cave-master", "--nodes", "2", "--path", &bad_path],
            "line 2",
        ),
        (
            vec!["cave-master", "--nodes", "2", "--head", "0,2,0"],
            "--head",
        ),
        (
            vec!["cave-master", "--nodes", "2", "--eye-separation", "2"],
            "--eye-separation",
        ),
        (
            vec!["cave-master", "--nodes", "2", "--node-timeout", "nan"],
            "--node-timeout",
        ),
        (
            vec!["cave-master", "--nodes", "1", "--listen", "256.1.1.1:1"],
            "cannot listen",
        ),
        (
            vec!["cave-master", "--nodes", "1", "--scene", "/no/such.toml"],
            "such",
        ),
        (
            vec!["cave-node", "--wall", "front", "--master", "nowhere:x"],
            "--master",
        ),
        (
            vec!["cave-node", "--wall", "front", "--connect-timeout", "-1"],
            "--connect-timeout",
        ),
    ] {
        let output = common::cli::vkgi(&args);
        common::cli::assert_bad_input(&output, needle);
    }
}
