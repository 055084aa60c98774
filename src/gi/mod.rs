//! Global-illumination techniques, one module each: persistent GPU state plus per-frame passes.
//! The frame (src/frame.rs) calls a technique twice: after the G-buffer to compute this frame's
//! indirect light, and after direct lighting to add it to the HDR image.

pub mod lpv;

use crate::frame::Frame;
use crate::gpu::{GpuResult, Recorder};

pub trait Technique {
    /// The passes that compute this frame's indirect light (after shadows and the G-buffer).
    fn record_light(&mut self, rec: &mut Recorder, frame: &Frame) -> GpuResult<()>;
    /// Add indirect radiance to `frame.hdr` (after direct lighting).
    fn record_lookup(&mut self, rec: &mut Recorder, frame: &Frame) -> GpuResult<()>;
    /// Lines for the profile: how the technique ran (lattice, tiles, queue plan...).
    fn describe(&self) -> Vec<String>;
}
