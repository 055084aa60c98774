//! The one loop that runs frames and collects their profile, for `render`, `report`,
//! `profile` and the benches: warm-up frames untimed, then measured frames, all finished; and
//! its animated form, which poses the scene's dynamic objects before each frame.

use super::frame::Frame;
use crate::gi::{Follow, GiMethod};
use crate::gpu::frames::FrameRing;
use crate::gpu::profiler::Profiler;
use crate::gpu::{Gpu, GpuResult};
use crate::scene::Scene;
use crate::scene::dynamic::Moved;

/// Frames in flight while running.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Run `warmup` frames whose times are dropped, then `measured` frames, and wait for all of
/// them. The returned ring's profiler holds the measured frames' passes and notes on how they
/// ran (queue plan, submit plan, the method's own description).
pub fn run_frames(
    gpu: &Gpu,
    frame: &mut Frame,
    mut gi: Option<&mut dyn GiMethod>,
    warmup: u32,
    measured: u32,
) -> GpuResult<FrameRing> {
    let mut ring = FrameRing::new(gpu, FRAMES_IN_FLIGHT)?;
    for _ in 0..warmup {
        frame.submit(
            gpu,
            &mut ring,
            gi.as_mut().map(|g| &mut **g as &mut dyn GiMethod),
        )?;
    }
    ring.finish()?;
    ring.profiler.clear();
    for _ in 0..measured {
        frame.submit(
            gpu,
            &mut ring,
            gi.as_mut().map(|g| &mut **g as &mut dyn GiMethod),
        )?;
    }
    ring.finish()?;
    add_notes(gpu, &mut ring.profiler, frame, gi.map(|g| &*g));
    Ok(ring)
}

/// Notes on how the frames ran: the queue plan, the method's description, its parts' plan, its
/// convergence and its status line.
pub fn add_notes(gpu: &Gpu, profiler: &mut Profiler, frame: &Frame, gi: Option<&dyn GiMethod>) {
    profiler.add_note(format!("queue plan: {}", gpu.queues.describe()));
    if let Some(gi) = gi {
        for line in gi.describe() {
            profiler.add_note(line);
        }
        if !gi.parts().is_empty() {
            profiler.add_note(format!(
                "{} independent parts ({}): {:?} plan",
                gi.parts().len(),
                gi.parts().join(", "),
                frame.submit_plan()
            ));
        }
        if let Some(c) = gi.convergence() {
            profiler.add_note(format!("convergence: {} {:.3e}", c.measure, c.remaining));
        }
        if let Some(status) = gi.status() {
            profiler.add_note(status);
        }
    }
}

/// Builds a GI method again for the scene as it is (after geometry moved that it cannot follow).
pub type Rebuild<'a> = dyn Fn(&Scene) -> anyhow::Result<Box<dyn GiMethod>> + 'a;

/// Run frames 0..`frames` of `scene`'s animation, all measured: before each, the dynamic
/// objects are posed for it and the objects that moved are handed to the frame and to the
/// method ([`follow`]).
pub fn run_animation(
    gpu: &Gpu,
    frame: &mut Frame,
    scene: &mut Scene,
    mut gi: Option<&mut Box<dyn GiMethod>>,
    rebuild: &Rebuild,
    frames: u32,
) -> anyhow::Result<FrameRing> {
    let mut ring = FrameRing::new(gpu, FRAMES_IN_FLIGHT)?;
    for index in 0..frames {
        let moved = scene.pose(u64::from(index));
        follow(
            gpu,
            &mut ring,
            frame,
            scene,
            &moved,
            gi.as_deref_mut(),
            rebuild,
        )?;
        frame.submit(
            gpu,
            &mut ring,
            gi.as_mut().map(|g| g.as_mut() as &mut dyn GiMethod),
        )?;
    }
    ring.finish()?;
    add_notes(gpu, &mut ring.profiler, frame, gi.map(|g| &**g));
    Ok(ring)
}

/// Hand the objects [`Scene::pose`] moved to the frame (their vertices) and to the method
/// (their regions); build the method again, once the frames in flight are done with it, where
/// it cannot follow. Returns whether it was built again.
pub fn follow(
    gpu: &Gpu,
    ring: &mut FrameRing,
    frame: &mut Frame,
    scene: &Scene,
    moved: &[Moved],
    gi: Option<&mut Box<dyn GiMethod>>,
    rebuild: &Rebuild,
) -> anyhow::Result<bool> {
    if moved.is_empty() {
        return Ok(false);
    }
    for m in moved {
        frame.set_vertices(scene, m.vertices.clone());
    }
    let Some(gi) = gi else {
        return Ok(false);
    };
    match gi.geometry_moved(gpu, scene, &Moved::regions(moved))? {
        Follow::Followed => Ok(false),
        Follow::Rebuild => {
            ring.finish()?;
            gpu.wait_idle()?;
            *gi = rebuild(scene)?;
            frame.restart_method();
            Ok(true)
        }
    }
}
