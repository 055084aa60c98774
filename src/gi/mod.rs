//! Global-illumination techniques, one module each: persistent GPU state plus per-frame passes.
//! The frame (src/frame.rs) calls a technique at three points: after the G-buffer (graphics
//! queue), once per colour channel (each may run on its own compute queue), and after direct
//! lighting to add indirect light to the HDR image.

pub mod lpv;

use crate::frame::{Frame, View};
use crate::gpu::{GpuResult, Recorder};

pub trait Technique {
    /// Passes on the graphics queue after shadows and the G-buffer (e.g. RSM, injection).
    fn record_light(&mut self, rec: &mut Recorder, frame: &Frame) -> GpuResult<()>;
    /// This frame's work for one colour channel (0 = R, 1 = G, 2 = B).
    fn record_channel(&mut self, rec: &mut Recorder, channel: usize) -> GpuResult<()>;
    /// Every channel of this frame is recorded: its light is the one lookups read from now.
    fn light_recorded(&mut self);
    /// Add indirect radiance to a view's HDR image (after its direct lighting and after
    /// [`Technique::light_recorded`]); called once per view.
    fn record_lookup(&self, rec: &mut Recorder, view: &View) -> GpuResult<()>;
    /// Lines for the profile: how the technique ran (lattice, tiles...).
    fn describe(&self) -> Vec<String>;
}
