//! The one loop that runs frames and collects their profile, for `render`, `report`,
//! `profile` and the benches: warm-up frames untimed, then measured frames, all finished.

use super::frame::Frame;
use crate::gi::GiMethod;
use crate::gpu::frames::FrameRing;
use crate::gpu::{Gpu, GpuResult};

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
    ring.profiler
        .add_note(format!("queue plan: {}", gpu.queues.describe()));
    if let Some(gi) = gi {
        for line in gi.describe() {
            ring.profiler.add_note(line);
        }
        if !gi.parts().is_empty() {
            ring.profiler.add_note(format!(
                "{} independent parts ({}): {:?} plan",
                gi.parts().len(),
                gi.parts().join(", "),
                frame.submit_plan()
            ));
        }
        if let Some(c) = gi.convergence() {
            ring.profiler
                .add_note(format!("convergence: {} {:.3e}", c.measure, c.remaining));
        }
    }
    Ok(ring)
}
