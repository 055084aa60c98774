//! `vkgi cave-node`: one wall of a CAVE run on its own Vulkan device. It joins the master, then
//! for every frame the master releases: applies the frame's parameter updates (and says so at
//! once), renders the whole frame for its wall (shadows, RSM, injection, propagation: nothing is
//! shared between nodes but the parameters), waits for its GPU, and reports the frame finished
//! with a digest of its GI method's lattices. It shows its wall in a window (or renders
//! headless with --headless); --screenshot saves it when the master stops the run.

use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Context;
use glam::Vec3;

use super::display::{Display, Opened};
use super::protocol::{self, Link, LinkError, MasterMessage, NodeMessage, RunSettings};
use super::stereo::{self, StereoLayout};
use crate::app::cli::CaveNodeArgs;
use crate::app::{method, output};
use crate::gi::GiMethod;
use crate::gpu::frames::FrameRing;
use crate::gpu::{Gpu, GpuOptions};
use crate::imageio::{self, ImageKind};
use crate::render::runner::{self, FRAMES_IN_FLIGHT};
use crate::render::{Frame, FrameOptions};
use crate::scene::Scene;
use crate::view::cave::{Cave, EyeChoice, WallName};

pub fn run(args: &CaveNodeArgs) -> anyhow::Result<()> {
    let (wall, eye) = (args.wall, args.eye);
    let tag = format!("cave-node {}", super::node_name(wall.name(), eye));
    let connect_timeout = super::seconds(args.connect_timeout, "connect-timeout")?;
    let master_timeout = super::seconds(args.master_timeout, "master-timeout")?;
    let limit = crate::render::MAX_IMAGE_SIDE;
    let (width, height) = args.size;
    if width == 0 || height == 0 || width.max(height) > limit {
        crate::bad_input!("--size must be 1..={limit} on each side");
    }
    let side = view_side(args.size, eye, args.stereo);
    let screenshot = args
        .screenshot
        .as_ref()
        .map(|prefix| Screenshot::new(prefix, wall, eye))
        .transpose()?;
    let mut scene = Scene::load(&args.scene)?;

    let master = resolve(&args.master)?;
    // The window opens first: a node that cannot show its wall never joins the run.
    let opened = match args.headless {
        true => None,
        false => Some(Opened::new(&format!("vkgi: {tag}"), args.size)?),
    };
    let mut link = connect(&master, &args.master, connect_timeout, &tag)?;
    link.send(&NodeMessage::Hello {
        build: protocol::build(),
        wall: wall.name().into(),
        eye,
        scene: crate::reference::cache::scene_hash(&scene),
        scene_name: scene.name.clone(),
    })?;
    let run = welcome(&mut link, master_timeout, &args.master)?;
    scene.area_samples = run.area_samples;
    let chosen = method::choose(&run.method, &run.settings)?;

    let gpu = Gpu::new(&GpuOptions {
        display: opened.as_ref().map(Opened::display).transpose()?,
        ..args.gpu.options()
    })
    .context("setting up the GPU")?;
    let (mut cave, fly) = Cave::placed_with_fly(&scene, run.cave_size, Vec3::ZERO);
    let options = FrameOptions {
        width: side,
        height: side,
        ..run.frame.clone()
    };
    let views = |cave: &mut Cave, scene: &Scene| {
        cave.follow(&fly);
        let mut drawn = cave.all_walls()[wall.index()];
        if run.edge_pixels {
            drawn = drawn.edge_centred(side);
        }
        eye.eyes(cave, scene, &drawn, run.eye_separation)
    };
    let first_eyes = views(&mut cave, &scene);
    let mut frame = Frame::with_eyes(&gpu, &scene, options, &first_eyes)?;
    let mut gi = method::build_if_chosen(&gpu, &scene, chosen.as_ref())?;
    let rebuild = |scene: &Scene| method::rebuild(&gpu, scene, chosen.as_ref());
    let mut ring = FrameRing::new(&gpu, FRAMES_IN_FLIGHT)?;
    let mut display = opened
        .map(|o| Display::new(&gpu, o, first_eyes.len(), args.stereo, FRAMES_IN_FLIGHT))
        .transpose()?;
    link.send(&NodeMessage::Ready)?;
    println!("{tag}: joined; rendering {side}x{side} with {}", run.method);

    let mut version = 0u64;
    let mut frames = 0u64;
    let mut finished_at: Option<Instant> = None;
    let mut last_render_ms = 0.0;
    loop {
        // The master may still be waiting for slower nodes to set up before the first frame.
        let wait = match frames {
            0 => master_timeout + run.join_timeout(),
            _ => master_timeout,
        };
        let message = next_message(&mut link, display.as_mut(), wait)
            .map_err(|e| anyhow::anyhow!("lost the master after {frames} frame(s): {e}"))?;
        let (number, since, next, updates, figures) = match message {
            MasterMessage::Frame {
                frame,
                since,
                version,
                updates,
                sync_ms,
                lock_wait_ms,
            } => (frame, since, version, updates, (sync_ms, lock_wait_ms)),
            MasterMessage::Stop { reason } => {
                println!("{tag}: stopping after {frames} frame(s): {reason}");
                break;
            }
            other => anyhow::bail!("the master sent {other:?} during the run"),
        };
        let lock_wait_ms = finished_at.map_or(0.0, |t| t.elapsed().as_secs_f64() * 1e3);
        if number != frames || since != version {
            anyhow::bail!(
                "out of step: the master sent frame {number} from version {since}, this node is at frame {frames}, version {version}"
            );
        }
        super::apply(&updates, &mut scene, &mut frame, &mut cave);
        version = next;
        link.send(&NodeMessage::Applied {
            frame: number,
            version,
        })?;
        let moved = scene.pose(number);
        runner::follow(
            &gpu,
            &mut ring,
            &mut frame,
            &scene,
            &moved,
            gi.as_mut(),
            &rebuild,
        )?;
        frame.set_eyes(&views(&mut cave, &scene));
        let start = Instant::now();
        let method = gi.as_deref_mut().map(|g| g as &mut dyn GiMethod);
        match &mut display {
            Some(display) => {
                let lines = overlay_lines(&tag, number, version, figures, last_render_ms);
                display.render(&gpu, &mut ring, &mut frame, method, &lines)?;
            }
            None => frame.submit(&gpu, &mut ring, method)?,
        }
        ring.finish()?;
        let render_ms = start.elapsed().as_secs_f64() * 1e3;
        last_render_ms = render_ms;
        let lattice = match &gi {
            Some(g) => g.state_digest(&gpu)?,
            None => None,
        };
        link.send(&NodeMessage::Finished {
            frame: number,
            version,
            lattice,
            lock_wait_ms,
            render_ms,
        })?;
        finished_at = Some(Instant::now());
        frames += 1;
    }
    if let Some(screenshot) = &screenshot {
        if frames == 0 {
            anyhow::bail!("stopped before the first frame: nothing to save");
        }
        screenshot.save(&gpu, &frame, args.stereo, display.as_ref())?;
        println!("{tag}: saved {}", screenshot.describe(display.is_some()));
    }
    crate::app::render::check_validation(&gpu)
}

/// The master's answer to the hello: its welcome (checked), or its refusal as one line of bad
/// input.
fn welcome(link: &mut Link, timeout: Duration, master: &str) -> anyhow::Result<RunSettings> {
    match link.receive(timeout) {
        Ok(MasterMessage::Welcome(run)) => {
            run.check()?;
            Ok(run)
        }
        Ok(MasterMessage::Refused { reason }) => {
            crate::bad_input!("refused by the master: {reason}")
        }
        Ok(other) => anyhow::bail!("the master began with {other:?} instead of a welcome"),
        Err(e) => anyhow::bail!("no welcome from the master at {master}: {e}"),
    }
}

/// The side of the node's square views: the largest that fits its window (`size`), one view
/// or a stereo pair laid out side by side or top-bottom (an anaglyph overlays the pair).
fn view_side((width, height): (u32, u32), eye: EyeChoice, layout: StereoLayout) -> u32 {
    match (eye, layout) {
        (EyeChoice::Both, StereoLayout::SideBySide) => (width / 2).min(height),
        (EyeChoice::Both, StereoLayout::TopBottom) => width.min(height / 2),
        _ => width.min(height),
    }
    .max(1)
}

/// The master's next message, keeping the window (if any) responsive while waiting.
fn next_message(
    link: &mut Link,
    mut display: Option<&mut Display>,
    timeout: Duration,
) -> anyhow::Result<MasterMessage> {
    let deadline = Instant::now() + timeout;
    loop {
        let slice = deadline
            .saturating_duration_since(Instant::now())
            .min(Duration::from_millis(20));
        match link.receive::<MasterMessage>(slice) {
            Ok(message) => return Ok(message),
            Err(LinkError::Timeout(_)) if Instant::now() < deadline => {
                if let Some(display) = display.as_deref_mut()
                    && !display.pump()
                {
                    anyhow::bail!("its window was closed");
                }
            }
            Err(LinkError::Timeout(_)) => {
                anyhow::bail!("no message within {:.1} s", timeout.as_secs_f64())
            }
            Err(e) => return Err(e.into()),
        }
    }
}

/// The overlay: who the node is, the frame and version it shows, the master's sync figures of
/// the frame before, and its own render time.
fn overlay_lines(
    tag: &str,
    frame: u64,
    version: u64,
    (sync_ms, lock_wait_ms): (f64, f64),
    render_ms: f64,
) -> Vec<String> {
    vec![
        tag.to_uppercase(),
        format!("FRAME {}  VERSION {version}", frame + 1),
        format!("SYNC {sync_ms:.3} MS  LOCK WAIT {lock_wait_ms:.3} MS"),
        format!("RENDER {render_ms:.1} MS"),
    ]
}

/// Where a node saves its views: PNG and EXR per view, and with both eyes the laid-out pair.
struct Screenshot {
    /// PNG and EXR of every view, in view order.
    views: Vec<(PathBuf, PathBuf)>,
    stereo: Option<PathBuf>,
    /// The window image with its overlay (windowed nodes only).
    window: PathBuf,
}

impl Screenshot {
    /// The paths for `prefix`, checked before any work.
    fn new(prefix: &Path, wall: WallName, eye: EyeChoice) -> anyhow::Result<Screenshot> {
        let with = |suffix: &str| {
            let mut name = prefix.as_os_str().to_owned();
            name.push(format!("-{}{suffix}", wall.name()));
            PathBuf::from(name)
        };
        let pair = |suffix: &str| -> anyhow::Result<(PathBuf, PathBuf)> {
            let (png, exr) = (
                with(&format!("{suffix}.png")),
                with(&format!("{suffix}.exr")),
            );
            imageio::check_image_output(&png, ImageKind::Ldr)?;
            imageio::check_image_output(&exr, ImageKind::Hdr)?;
            Ok((png, exr))
        };
        let (views, stereo) = match eye {
            EyeChoice::Mono => (vec![pair("")?], None),
            EyeChoice::Left => (vec![pair("-left")?], None),
            EyeChoice::Right => (vec![pair("-right")?], None),
            EyeChoice::Both => {
                let stereo = with("-stereo.png");
                imageio::check_image_output(&stereo, ImageKind::Ldr)?;
                (vec![pair("-left")?, pair("-right")?], Some(stereo))
            }
        };
        let window = with("-window.png");
        imageio::check_image_output(&window, ImageKind::Ldr)?;
        Ok(Screenshot {
            views,
            stereo,
            window,
        })
    }

    fn save(
        &self,
        gpu: &Gpu,
        frame: &Frame,
        layout: StereoLayout,
        display: Option<&Display>,
    ) -> anyhow::Result<()> {
        let (width, height) = (frame.options.width, frame.options.height);
        for (index, (png, exr)) in self.views.iter().enumerate() {
            output::write_view(gpu, frame, index, png, exr)?;
        }
        if let Some(path) = &self.stereo {
            let (left, right) = (frame.read_view_ldr(gpu, 0)?, frame.read_view_ldr(gpu, 1)?);
            let (pixels, (w, h)) = stereo::compose(layout, &left, &right, (width, height));
            imageio::write_png(path, w, h, &pixels)?;
        }
        if let Some(display) = display {
            let (pixels, (w, h)) = display.read_window(gpu)?;
            imageio::write_png(&self.window, w, h, &pixels)?;
        }
        Ok(())
    }

    fn describe(&self, windowed: bool) -> String {
        let mut names: Vec<String> = self
            .views
            .iter()
            .flat_map(|(png, exr)| [png.display().to_string(), exr.display().to_string()])
            .collect();
        names.extend(self.stereo.iter().map(|p| p.display().to_string()));
        if windowed {
            names.push(self.window.display().to_string());
        }
        names.join(", ")
    }
}

/// The master's socket address.
fn resolve(address: &str) -> anyhow::Result<Vec<SocketAddr>> {
    let addresses: Vec<_> = address
        .to_socket_addrs()
        .map_err(|e| crate::error::InputError::new(format!("--master {address}: {e}")))?
        .collect();
    if addresses.is_empty() {
        crate::bad_input!("--master {address} names no address");
    }
    Ok(addresses)
}

/// Connect to the master at any of `targets`, trying again until `timeout` (a node may start
/// before its master).
fn connect(
    targets: &[SocketAddr],
    address: &str,
    timeout: Duration,
    tag: &str,
) -> anyhow::Result<Link> {
    let deadline = Instant::now() + timeout;
    let mut said_waiting = false;
    loop {
        // The addresses in turn, stopping at the first that answers.
        let mut connected = Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "no address",
        ));
        for target in targets {
            connected = TcpStream::connect_timeout(target, Duration::from_secs(1));
            if connected.is_ok() {
                break;
            }
        }
        match connected {
            Ok(stream) => return Ok(Link::new(stream)?),
            Err(e) if Instant::now() >= deadline => {
                anyhow::bail!(
                    "no master at {address} within {:.0} s: {e}",
                    timeout.as_secs_f64()
                )
            }
            Err(_) => {
                if !said_waiting {
                    println!("{tag}: waiting for the master at {address}");
                    said_waiting = true;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }
    }
}
