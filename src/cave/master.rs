//! `vkgi cave-master`: waits for its nodes, then runs the frames. Each frame it sends every node
//! the parameter updates since the last (a new version when anything changed), waits until all
//! hold them (the parameter-sync latency) and all finished the frame, and only then releases
//! the next: the frame lock. The nodes render; the master uses a GPU only for its window's
//! overlay (`--window`).

use std::net::TcpListener;
use std::time::{Duration, Instant};

use anyhow::Context;
use serde::Serialize;

use super::display::{Display, Opened};
use super::input::Input;
use super::path::TrackedPath;
use super::protocol::{self, Link, LinkError, MasterMessage, NodeMessage, RunSettings};
use super::stereo::StereoLayout;
use super::{Pose, updates};
use crate::app::cli::{CaveMasterArgs, OnLoss};
use crate::app::method;
use crate::gpu::frames::FrameRing;
use crate::gpu::{Gpu, GpuOptions};
use crate::imageio::ImageKind;
use crate::render::runner::FRAMES_IN_FLIGHT;
use crate::scene::Scene;
use crate::view::cave::EyeChoice;
use winit::keyboard::KeyCode;

/// A node that joined.
struct Node {
    wall: String,
    eye: EyeChoice,
    link: Link,
}

impl Node {
    fn name(&self) -> String {
        super::node_name(&self.wall, self.eye)
    }
}

/// How long a new connection has to say hello.
const HELLO_TIMEOUT: Duration = Duration::from_secs(10);

/// One frame as the master saw it.
#[derive(Serialize)]
struct FrameRecord {
    frame: u64,
    version: u64,
    /// Send to the last node's acknowledgement of the frame's parameters, in milliseconds.
    sync_ms: f64,
    /// The longest wait of any node for this frame after it finished the last.
    lock_wait_ms: f64,
    /// The slowest node's GPU time for the frame.
    render_ms: f64,
    /// Wall and lattice digest of every node that finished the frame.
    lattices: Vec<(String, Option<String>)>,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    method: String,
    settings: Vec<(String, String)>,
    walls: Vec<String>,
    lost: Vec<String>,
    frames: Vec<FrameRecord>,
    /// Frames whose nodes' lattice digests were not all equal.
    differing_frames: Vec<u64>,
}

/// Check the flags before any work; the join and node timeouts.
fn check_args(args: &CaveMasterArgs) -> anyhow::Result<(Duration, Duration)> {
    let join_timeout = super::seconds(args.join_timeout, "join-timeout")?;
    let node_timeout = super::seconds(args.node_timeout, "node-timeout")?;
    if args.frames == 0 {
        crate::bad_input!("--frames must be at least 1");
    }
    crate::view::cave::check_size(args.cave_size)?;
    if !(args.eye_separation.is_finite() && (0.0..=1.0).contains(&args.eye_separation)) {
        crate::bad_input!("--eye-separation must be in [0, 1] (a fraction of the wall size)");
    }
    if args.head.abs().max_element() > 1.0 {
        crate::bad_input!("--head {} leaves the CAVE (each within ±1)", args.head);
    }
    if let Some(report) = &args.report {
        crate::imageio::check_destination(report)?;
    }
    Ok((join_timeout, node_timeout))
}

pub fn run(args: &CaveMasterArgs) -> anyhow::Result<()> {
    let (join_timeout, node_timeout) = check_args(args)?;
    let scene = Scene::load(&args.scene)?;
    let path = args.path.as_deref().map(TrackedPath::load).transpose()?;
    if let Some(path) = &path {
        path.check_scene(&scene)?;
    }
    // The window opens before any node joins: a master without a display fails at once.
    let mut console = args.window.then(|| Console::open(args)).transpose()?;
    let settings = deterministic(&args.gi.method, &args.gi.settings.values)?;
    let scene_digest = crate::reference::cache::scene_hash(&scene);

    let listener = TcpListener::bind(&args.listen).map_err(|e| {
        crate::error::InputError::new(format!("cannot listen on {}: {e}", args.listen))
    })?;
    println!(
        "cave-master: listening on {} for {} node(s)",
        listener.local_addr()?,
        args.nodes
    );
    let welcome = MasterMessage::Welcome(RunSettings {
        method: args.gi.method.clone(),
        settings: settings.clone(),
        cave_size: args.cave_size,
        eye_separation: args.eye_separation,
        edge_pixels: args.edge_pixels,
        frame: args.frame.options(),
        area_samples: args.frame.area_samples,
        join_timeout_s: join_timeout.as_secs_f64(),
    });
    let joined = Instant::now();
    let mut nodes = join(&listener, args, &scene_digest, &welcome, join_timeout)?;
    wait_until_ready(&mut nodes, joined + join_timeout, node_timeout)?;
    let mut report = Report {
        scene: scene.name.clone(),
        method: args.gi.method.clone(),
        settings,
        walls: nodes.iter().map(Node::name).collect(),
        lost: Vec::new(),
        frames: Vec::new(),
        differing_frames: Vec::new(),
    };

    let scene_light = scene.lights.first().map(|l| l.position);
    let diagonal = (scene.bounds_max - scene.bounds_min).length();
    let mut input = Input::new(path, args.head, scene_light, diagonal);
    let mut sent: Option<Pose> = None;
    let mut version = 0u64;
    let mut stopped = None;
    for frame in 0..args.frames {
        let pose = match read_input(args, console.as_mut(), &mut input, frame) {
            Ok(pose) => pose,
            Err(why) => {
                stopped = Some(why);
                break;
            }
        };
        let changes = updates(sent.as_ref(), &pose);
        let since = version;
        if !changes.is_empty() {
            version += 1;
        }
        sent = Some(pose);
        let last = report.frames.last();
        let message = MasterMessage::Frame {
            frame,
            since,
            version,
            updates: changes,
            sync_ms: last.map_or(0.0, |r| r.sync_ms),
            lock_wait_ms: last.map_or(0.0, |r| r.lock_wait_ms),
        };
        let (record, lost) = run_frame(&mut nodes, &message, node_timeout);
        if record
            .lattices
            .iter()
            .any(|(_, d)| *d != record.lattices[0].1)
        {
            report.differing_frames.push(frame);
        }
        if args.log_frames {
            println!(
                "cave-master: frame {frame} (version {version}): sync {:.3} ms, lock wait {:.3} ms, slowest render {:.3} ms",
                record.sync_ms, record.lock_wait_ms, record.render_ms
            );
        }
        report.frames.push(record);
        for (i, why) in lost.into_iter().rev() {
            let node = nodes.remove(i);
            println!(
                "cave-master: lost the {} at frame {frame}: {why}",
                node.name()
            );
            report.lost.push(node.name());
        }
        if let Some(console) = &mut console {
            let lines = console_lines(&report, &nodes, &pose, args.frames);
            console.show(&lines)?;
        }
        if !report.lost.is_empty() && args.on_loss == OnLoss::Stop {
            stop(
                &mut nodes,
                "the master stops: a wall was lost",
                node_timeout,
            );
            write_report(args, &report)?;
            anyhow::bail!("stopped after losing the {}", report.lost.join(", "));
        }
        if nodes.is_empty() {
            write_report(args, &report)?;
            anyhow::bail!("every node was lost by frame {frame}");
        }
    }
    stop(
        &mut nodes,
        stopped.unwrap_or("all frames done"),
        node_timeout,
    );
    write_report(args, &report)?;
    if let (Some(console), Some(prefix)) = (&mut console, &args.screenshot) {
        console.save(prefix)?;
    }
    summarise(&report);
    if let Some(console) = &console {
        crate::app::render::check_validation(&console.gpu)?;
    }
    Ok(())
}

/// Wait until every node has set up its device and method (seconds: the join timeout covers
/// it, but each node gets at least `node_timeout`). A node that fails stops the run.
fn wait_until_ready(
    nodes: &mut Vec<Node>,
    deadline: Instant,
    node_timeout: Duration,
) -> anyhow::Result<()> {
    for i in 0..nodes.len() {
        let wait = deadline
            .saturating_duration_since(Instant::now())
            .max(node_timeout);
        let failure = match nodes[i].link.receive::<NodeMessage>(wait) {
            Ok(NodeMessage::Ready) => continue,
            Ok(other) => format!("it answered {other:?}"),
            Err(e) => describe(e, wait),
        };
        let name = nodes[i].name();
        stop(nodes, "a node failed to set up", node_timeout);
        anyhow::bail!("the {name} did not get ready: {failure}");
    }
    println!("cave-master: {} node(s) ready", nodes.len());
    Ok(())
}

/// This frame's pose from the input: the path or head, the scripted key, and the window's keys
/// and mouse. Err(why) when the input ends the run (the window closed, esc).
fn read_input(
    args: &CaveMasterArgs,
    console: Option<&mut Console>,
    input: &mut Input,
    frame: u64,
) -> Result<Pose, &'static str> {
    let mut held: Vec<KeyCode> = args.keys.get(frame as usize).copied().into_iter().collect();
    let mut dragged = (0.0, 0.0);
    if let Some(console) = console {
        if !console.display.pump() {
            return Err("the master's window was closed");
        }
        held.extend_from_slice(console.display.held_keys());
        dragged = console.display.take_drag();
    }
    if held.contains(&KeyCode::Escape) {
        return Err("stopped from the master's keyboard");
    }
    Ok(input.pose(frame, &held, dragged))
}

/// Send one frame to every node, then wait (at most `timeout` for all of them together, per
/// step) for every node to hold its parameters, then to finish it: k silent nodes cost one
/// timeout, not k. Returns the frame's record and the nodes lost on the way (their
/// indices, ascending, and why).
fn run_frame(
    nodes: &mut [Node],
    message: &MasterMessage,
    timeout: Duration,
) -> (FrameRecord, Vec<(usize, String)>) {
    let &MasterMessage::Frame { frame, version, .. } = message else {
        unreachable!("run_frame sends frames only");
    };
    let start = Instant::now();
    let mut lost: Vec<(usize, String)> = Vec::new();
    for (i, node) in nodes.iter_mut().enumerate() {
        if let Err(e) = node.link.send(message) {
            lost.push((i, describe(e, timeout)));
        }
    }
    let is_lost = |lost: &[(usize, String)], i: usize| lost.iter().any(|(l, _)| *l == i);
    // Every node acknowledges the parameters before it renders, then reports the frame.
    let mut record = FrameRecord {
        frame,
        version,
        sync_ms: 0.0,
        lock_wait_ms: 0.0,
        render_ms: 0.0,
        lattices: Vec::new(),
    };
    let deadline = start + timeout;
    for (i, node) in nodes.iter_mut().enumerate() {
        if is_lost(&lost, i) {
            continue;
        }
        match expect_applied(&mut node.link, frame, version, left(deadline), timeout) {
            Ok(()) => record.sync_ms = record.sync_ms.max(start.elapsed().as_secs_f64() * 1e3),
            Err(e) => lost.push((i, e)),
        }
    }
    let deadline = Instant::now() + timeout;
    for (i, node) in nodes.iter_mut().enumerate() {
        if is_lost(&lost, i) {
            continue;
        }
        match expect_finished(&mut node.link, frame, version, left(deadline), timeout) {
            Ok((lattice, wait, render)) => {
                record.lock_wait_ms = record.lock_wait_ms.max(wait);
                record.render_ms = record.render_ms.max(render);
                let digest = lattice.map(|d| format!("{d:016x}"));
                record.lattices.push((node.name(), digest));
            }
            Err(e) => lost.push((i, e)),
        }
    }
    lost.sort_by_key(|(i, _)| *i);
    (record, lost)
}

/// The time to `deadline`, but enough for one look at what a node already sent.
fn left(deadline: Instant) -> Duration {
    deadline
        .saturating_duration_since(Instant::now())
        .max(Duration::from_millis(20))
}

/// The master's window: a device only for its overlay, and the keyboard and mouse.
struct Console {
    // Field order is drop order: the window's GPU objects, then the ring, then the device.
    display: Display,
    ring: FrameRing,
    gpu: Gpu,
}

impl Console {
    fn open(args: &CaveMasterArgs) -> anyhow::Result<Console> {
        if let Some(prefix) = &args.screenshot {
            crate::imageio::check_image_output(&window_png(prefix), ImageKind::Ldr)?;
        }
        let opened = Opened::new("vkgi: CAVE master", args.frame.size)?;
        let gpu = Gpu::new(&GpuOptions {
            display: Some(opened.display()?),
            ..args.gpu.options()
        })
        .context("setting up the master's window")?;
        let ring = FrameRing::new(&gpu, FRAMES_IN_FLIGHT)?;
        let display = Display::new(&gpu, opened, 0, StereoLayout::SideBySide, FRAMES_IN_FLIGHT)?;
        Ok(Console { display, ring, gpu })
    }

    fn show(&mut self, lines: &[String]) -> anyhow::Result<()> {
        self.display.show_text(&self.gpu, &mut self.ring, lines)
    }

    fn save(&mut self, prefix: &std::path::Path) -> anyhow::Result<()> {
        self.ring.finish()?;
        let (pixels, (w, h)) = self.display.read_window(&self.gpu)?;
        let path = window_png(prefix);
        crate::imageio::write_png(&path, w, h, &pixels)?;
        println!("cave-master: saved {}", path.display());
        Ok(())
    }
}

fn window_png(prefix: &std::path::Path) -> std::path::PathBuf {
    let mut name = prefix.as_os_str().to_owned();
    name.push("-window.png");
    name.into()
}

/// The master's overlay: the run, the last frame's sync figures, the walls, the pose, the keys.
fn console_lines(report: &Report, nodes: &[Node], pose: &Pose, frames: u64) -> Vec<String> {
    let mut lines = vec![format!(
        "CAVE MASTER  {} NODE(S)  {} LOST",
        nodes.len(),
        report.lost.len()
    )];
    if let Some(last) = report.frames.last() {
        lines.push(format!(
            "FRAME {} OF {frames}  VERSION {}",
            last.frame + 1,
            last.version
        ));
        lines.push(format!(
            "SYNC {:.3} MS  LOCK WAIT {:.3} MS  SLOWEST RENDER {:.1} MS",
            last.sync_ms, last.lock_wait_ms, last.render_ms
        ));
    }
    let names: Vec<String> = nodes.iter().map(Node::name).collect();
    lines.push(names.join(", ").to_uppercase());
    if !report.lost.is_empty() {
        lines.push(format!("LOST: {}", report.lost.join(", ")).to_uppercase());
    }
    let h = pose.head;
    lines.push(format!("HEAD {:.2} {:.2} {:.2}", h.x, h.y, h.z));
    if let Some(l) = pose.light {
        lines.push(format!("LIGHT {:.3} {:.3} {:.3}", l.x, l.y, l.z));
    }
    lines.push(super::input::HELP.into());
    lines
}

/// The method's settings for every node, with the deterministic injection where the method has
/// one and the user did not choose (float atomics would let the nodes' lattices drift apart).
fn deterministic(
    method_name: &str,
    overrides: &[(String, String)],
) -> anyhow::Result<Vec<(String, String)>> {
    let mut settings = overrides.to_vec();
    if let Some(chosen) = method::choose(method_name, overrides)?
        && chosen.settings.has("injection")
        && !overrides.iter().any(|(name, _)| name == "injection")
    {
        settings.push(("injection".into(), "fixed".into()));
    }
    Ok(settings)
}

/// Accept nodes until `args.nodes` joined. Each says hello and is refused, with the reason in
/// one line on both ends, if its build or scene differs or its view is taken; a connection
/// that fails on the way is dropped without ending the run.
fn join(
    listener: &TcpListener,
    args: &CaveMasterArgs,
    scene_digest: &str,
    welcome: &MasterMessage,
    timeout: Duration,
) -> anyhow::Result<Vec<Node>> {
    listener.set_nonblocking(true)?;
    let deadline = Instant::now() + timeout;
    let mut nodes: Vec<Node> = Vec::new();
    while nodes.len() < args.nodes as usize {
        let stream = match listener.accept() {
            Ok((stream, _)) => stream,
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                if Instant::now() >= deadline {
                    let joined: Vec<String> = nodes.iter().map(Node::name).collect();
                    stop(&mut nodes, "the run did not start", Duration::from_secs(1));
                    anyhow::bail!(
                        "only {} of {} node(s) joined within {:.0} s (walls: {})",
                        joined.len(),
                        args.nodes,
                        timeout.as_secs_f64(),
                        if joined.is_empty() {
                            "none".to_string()
                        } else {
                            joined.join(", ")
                        }
                    );
                }
                std::thread::sleep(Duration::from_millis(5));
                continue;
            }
            Err(e) => {
                println!("cave-master: accepting a connection failed: {e}");
                continue;
            }
        };
        match greet(stream, args, scene_digest, welcome, &nodes) {
            Ok(node) => {
                nodes.push(node);
                println!(
                    "cave-master: the {} joined ({} of {})",
                    nodes.last().map_or(String::new(), Node::name),
                    nodes.len(),
                    args.nodes
                );
            }
            Err(why) => println!("cave-master: {why}"),
        }
    }
    Ok(nodes)
}

/// Hear a connection's hello and welcome it as a node, or say why not.
fn greet(
    stream: std::net::TcpStream,
    args: &CaveMasterArgs,
    scene_digest: &str,
    welcome: &MasterMessage,
    nodes: &[Node],
) -> Result<Node, String> {
    let mut link = stream
        .set_nonblocking(false)
        .and_then(|()| Link::new(stream))
        .map_err(|e| format!("a connection failed: {e}"))?;
    let (build, wall, eye, scene, scene_name) = match link.receive::<NodeMessage>(HELLO_TIMEOUT) {
        Ok(NodeMessage::Hello {
            build,
            wall,
            eye,
            scene,
            scene_name,
        }) => (build, wall, eye, scene, scene_name),
        Ok(other) => {
            return Err(refuse(
                &mut link,
                format!("it began with {other:?}, not a hello"),
            ));
        }
        Err(LinkError::Malformed(e)) => {
            let reason = format!("its hello is not one of {}: {e}", protocol::build());
            return Err(refuse(&mut link, reason));
        }
        Err(e) => return Err(format!("a connection said no hello: {e}")),
    };
    let name = super::node_name(&wall, eye);
    let reason = if build != protocol::build() {
        format!(
            "its build is '{build}', the master's '{}'",
            protocol::build()
        )
    } else if scene != scene_digest {
        format!(
            "its scene '{scene_name}' (digest {scene}) is not the master's '{}' (digest {scene_digest})",
            args.scene
        )
    } else if nodes.iter().any(|n| n.wall == wall && n.eye.overlaps(eye)) {
        format!("the {name} view is taken")
    } else {
        link.send(welcome)
            .map_err(|e| format!("the {name} left before its welcome: {e}"))?;
        return Ok(Node { wall, eye, link });
    };
    Err(format!("refused the {name}: {}", refuse(&mut link, reason)))
}

/// Tell a connection it cannot join (it may already be gone); returns the reason.
fn refuse(link: &mut Link, reason: String) -> String {
    let _ = link.send(&MasterMessage::Refused {
        reason: reason.clone(),
    });
    reason
}

fn expect_applied(
    link: &mut Link,
    frame: u64,
    version: u64,
    wait: Duration,
    timeout: Duration,
) -> Result<(), String> {
    match link.receive::<NodeMessage>(wait) {
        Ok(NodeMessage::Applied {
            frame: f,
            version: v,
        }) if (f, v) == (frame, version) => Ok(()),
        Ok(other) => Err(format!(
            "it answered {other:?} to frame {frame} (version {version})"
        )),
        Err(e) => Err(describe(e, timeout)),
    }
}

fn expect_finished(
    link: &mut Link,
    frame: u64,
    version: u64,
    wait: Duration,
    timeout: Duration,
) -> Result<(Option<u64>, f64, f64), String> {
    match link.receive::<NodeMessage>(wait) {
        Ok(NodeMessage::Finished {
            frame: f,
            version: v,
            lattice,
            lock_wait_ms,
            render_ms,
        }) if (f, v) == (frame, version) => Ok((lattice, lock_wait_ms, render_ms)),
        Ok(other) => Err(format!(
            "it answered {other:?} while finishing frame {frame}"
        )),
        Err(e) => Err(describe(e, timeout)),
    }
}

/// Why a node is lost, in words; `timeout` is how long it had.
fn describe(error: LinkError, timeout: Duration) -> String {
    match error {
        LinkError::Timeout(_) => format!(
            "it stopped answering (nothing for {:.1} s)",
            timeout.as_secs_f64()
        ),
        LinkError::Closed => "its connection closed (the node died or quit)".into(),
        other => other.to_string(),
    }
}

/// Tell every node to stop, and wait (at most `timeout` each) until it closed its end, so the
/// master exits after its nodes saved what they were asked to.
fn stop(nodes: &mut Vec<Node>, reason: &str, timeout: Duration) {
    for node in nodes.iter_mut() {
        let _ = node.link.send(&MasterMessage::Stop {
            reason: reason.into(),
        });
    }
    for node in nodes.iter_mut() {
        while node.link.receive::<NodeMessage>(timeout).is_ok() {}
    }
    nodes.clear();
}

fn write_report(args: &CaveMasterArgs, report: &Report) -> anyhow::Result<()> {
    if let Some(path) = &args.report {
        crate::imageio::write_text(path, &serde_json::to_string_pretty(report)?)?;
    }
    Ok(())
}

fn summarise(report: &Report) {
    let frames = report.frames.len();
    let median = |mut values: Vec<f64>| {
        values.sort_by(f64::total_cmp);
        values.get(values.len() / 2).copied().unwrap_or(0.0)
    };
    let sync = median(report.frames.iter().map(|f| f.sync_ms).collect());
    let wait = median(report.frames.iter().map(|f| f.lock_wait_ms).collect());
    let lattices = if report
        .frames
        .iter()
        .all(|f| f.lattices.iter().all(|(_, d)| d.is_none()))
    {
        "the method carries no lattice".to_string()
    } else if report.differing_frames.is_empty() {
        "lattices bit-identical on every frame".to_string()
    } else {
        format!(
            "lattices differed on {} frame(s), first {}",
            report.differing_frames.len(),
            report.differing_frames[0]
        )
    };
    println!(
        "cave-master: {frames} frames on {} node(s) ({} lost); parameter sync median {sync:.3} ms, frame-lock wait median {wait:.3} ms; {lattices}",
        report.walls.len() - report.lost.len(),
        report.lost.len()
    );
}
