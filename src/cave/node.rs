//! `vkgi cave-node`: one wall of a CAVE run on its own Vulkan device. It joins the master, then
//! for every frame the master releases: applies the frame's parameter updates (and says so at
//! once), renders the whole frame for its wall (shadows, RSM, injection, propagation: nothing is
//! shared between nodes but the parameters), waits for its GPU, and reports the frame finished
//! with a digest of its GI method's lattices. It renders headless; --screenshot saves its wall
//! when the master stops the run.

use std::net::{TcpStream, ToSocketAddrs};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Context;
use glam::Vec3;

use super::protocol::{self, Link, MasterMessage, NodeMessage};
use crate::app::cli::CaveNodeArgs;
use crate::app::{method, output};
use crate::gi::GiMethod;
use crate::gpu::Gpu;
use crate::gpu::frames::FrameRing;
use crate::imageio::{self, HdrImage, ImageKind};
use crate::render::runner::{self, FRAMES_IN_FLIGHT};
use crate::render::{Eye, Frame, FrameOptions};
use crate::scene::Scene;
use crate::view::cave::{Cave, WallName};
use crate::view::fly::FlyCamera;

pub fn run(args: &CaveNodeArgs) -> anyhow::Result<()> {
    let wall = args.wall;
    let tag = format!("cave-node {}", wall.name());
    let seconds = |value: f64, flag: &str| -> anyhow::Result<Duration> {
        if !(value.is_finite() && value > 0.0 && value <= 86_400.0) {
            crate::bad_input!("--{flag} must be in (0, 86400] seconds");
        }
        Ok(Duration::from_secs_f64(value))
    };
    let connect_timeout = seconds(args.connect_timeout, "connect-timeout")?;
    let master_timeout = seconds(args.master_timeout, "master-timeout")?;
    let side = args.frame.size.0.min(args.frame.size.1);
    let limit = crate::render::MAX_IMAGE_SIDE;
    if side == 0 || args.frame.size.0.max(args.frame.size.1) > limit {
        crate::bad_input!("--size must be 1..={limit} on each side");
    }
    let screenshot = args
        .screenshot
        .as_ref()
        .map(|prefix| screenshot_paths(prefix, wall))
        .transpose()?;
    let mut scene = Scene::load(&args.scene)?;
    scene.area_samples = args.frame.area_samples;

    let mut link = connect(&args.master, connect_timeout, &tag)?;
    link.send(&NodeMessage::Hello {
        build: protocol::build(),
        wall: wall.name().into(),
        scene: crate::reference::cache::scene_hash(&scene),
        scene_name: scene.name.clone(),
    })?;
    let (method_name, settings, cave_size) = match link.receive(master_timeout) {
        Ok(MasterMessage::Welcome {
            method,
            settings,
            cave_size,
        }) => (method, settings, cave_size),
        Ok(MasterMessage::Refused { reason }) => {
            crate::bad_input!("refused by the master: {reason}")
        }
        Ok(other) => anyhow::bail!("the master began with {other:?} instead of a welcome"),
        Err(e) => anyhow::bail!("no welcome from the master at {}: {e}", args.master),
    };
    if !(cave_size.is_finite() && cave_size > 0.0 && cave_size <= 100.0) {
        anyhow::bail!("the master sent a CAVE size of {cave_size}");
    }
    let chosen = method::choose(&method_name, &settings)?;

    let gpu = Gpu::new(&args.gpu.options()).context("setting up the GPU")?;
    let (mut cave, fly) = Cave::placed_with_fly(&scene, cave_size, Vec3::ZERO);
    let options = FrameOptions {
        width: side,
        height: side,
        ..args.frame.options()
    };
    let first_eye = wall_eye(&mut cave, &fly, &scene, wall);
    let mut frame = Frame::with_eyes(&gpu, &scene, options, &[first_eye])?;
    let mut gi = match &chosen {
        Some(c) => Some(method::build(&gpu, &scene, c, None)?),
        None => None,
    };
    let rebuild = |scene: &Scene| match &chosen {
        Some(c) => method::build(&gpu, scene, c, None),
        None => anyhow::bail!("no GI method to build"),
    };
    let mut ring = FrameRing::new(&gpu, FRAMES_IN_FLIGHT)?;
    link.send(&NodeMessage::Ready)?;
    println!("{tag}: joined; rendering {side}x{side} with {method_name}");

    let mut version = 0u64;
    let mut frames = 0u64;
    let mut finished_at: Option<Instant> = None;
    loop {
        let message = link
            .receive::<MasterMessage>(master_timeout)
            .map_err(|e| anyhow::anyhow!("lost the master after {frames} frame(s): {e}"))?;
        let (number, since, next, updates) = match message {
            MasterMessage::Frame {
                frame,
                since,
                version,
                updates,
                ..
            } => (frame, since, version, updates),
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
        frame.set_eyes(&[wall_eye(&mut cave, &fly, &scene, wall)]);
        let start = Instant::now();
        frame.submit(
            &gpu,
            &mut ring,
            gi.as_deref_mut().map(|g| g as &mut dyn GiMethod),
        )?;
        ring.finish()?;
        let render_ms = start.elapsed().as_secs_f64() * 1e3;
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
    if let Some((png, exr)) = &screenshot {
        let size = (side, side);
        output::write_images(
            Some(png),
            Some(exr),
            || Ok(frame.read_ldr(&gpu)?),
            || Ok(HdrImage::new(side, side, frame.read_hdr(&gpu)?)),
            size,
        )?;
        println!("{tag}: saved {} and {}", png.display(), exr.display());
    }
    crate::app::render::check_validation(&gpu)
}

/// The eye of the head through `wall` of the CAVE `fly` carries (as `vkgi view --cave` makes
/// it).
fn wall_eye(cave: &mut Cave, fly: &FlyCamera, scene: &Scene, wall: WallName) -> Eye {
    cave.follow(fly);
    cave.eye(scene, &cave.all_walls()[wall.index()])
}

/// PREFIX-WALL.png and PREFIX-WALL.exr, checked before any work.
fn screenshot_paths(
    prefix: &std::path::Path,
    wall: WallName,
) -> anyhow::Result<(PathBuf, PathBuf)> {
    let with = |extension: &str| {
        let mut name = prefix.as_os_str().to_owned();
        name.push(format!("-{}.{extension}", wall.name()));
        PathBuf::from(name)
    };
    let (png, exr) = (with("png"), with("exr"));
    imageio::check_image_output(&png, ImageKind::Ldr)?;
    imageio::check_image_output(&exr, ImageKind::Hdr)?;
    Ok((png, exr))
}

/// Connect to the master, trying again until `timeout` (a node may start before its master).
fn connect(address: &str, timeout: Duration, tag: &str) -> anyhow::Result<Link> {
    let addresses: Vec<_> = address
        .to_socket_addrs()
        .map_err(|e| crate::error::InputError::new(format!("--master {address}: {e}")))?
        .collect();
    let Some(&target) = addresses.first() else {
        crate::bad_input!("--master {address} names no address");
    };
    let deadline = Instant::now() + timeout;
    let mut said_waiting = false;
    loop {
        match TcpStream::connect_timeout(&target, Duration::from_secs(1)) {
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
