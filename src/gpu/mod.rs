//! The hand-written Vulkan layer: the only module that calls `ash`.
//!
//! * [`context`]: instance, validation, device choice and the queue plan.
//! * [`memory`]: buffers and images on gpu-allocator, uploads and readbacks.
//! * [`reflect`] and [`pipeline`]: pipelines from the embedded SPIR-V, with their interface read
//!   from the SPIR-V itself so every pass's bindings are checked against the shader.
//! * [`pass`]: the one place a pass is recorded (debug label, timestamp scope, barriers).
//! * [`profiler`]: timestamp queries in a ring of frames in flight.
//! * [`frames`]: the ring of command buffers and fences the frame loop records into.
//! * [`dispatch`]: the shapes of compute dispatches every device accepts.
//! * [`scope`] and [`push`]: typed tags of timed passes; push constants with checked layouts.
#![deny(clippy::undocumented_unsafe_blocks)]

pub mod context;
pub mod dispatch;
pub mod frames;
pub mod memory;
pub mod pass;
pub mod pipeline;
pub mod profiler;
pub mod push;
pub mod reflect;
pub mod scope;
pub mod swapchain;

pub use context::{
    ConservativeRasterization, DescriptorLimits, Gpu, GpuOptions, PixelPasses, Queue, QueuePlan,
};
pub use memory::{Buffer, BufferDesc, Image, ImageDesc, Sampler};
pub use pass::{Binding, ComputePass, Draw, RasterPass, Recorder, ResourceKey, ResourceUse};
pub use pipeline::{ComputePipeline, Depth, RasterPipeline, RasterPipelineDesc, Specialization};
pub use profiler::{PassTiming, ProfileReport, Profiler};
pub use push::PushConstants;
pub use scope::{Part, ScopeTag, Stage};

use ash::vk;

/// An error of the Vulkan layer: what was being done, and what Vulkan said.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("Vulkan error while {what}: {result}")]
    Vulkan { what: String, result: vk::Result },
    #[error("{0}")]
    Setup(String),
    /// `--device` named no device (the user's input, not a failure).
    #[error("{0}")]
    NoSuchDevice(String),
    #[error("out of GPU memory or allocation failed for {what}: {message}")]
    Allocation { what: String, message: String },
    #[error("shader interface mismatch in {pass}: {message}")]
    Interface { pass: String, message: String },
}

pub type GpuResult<T> = Result<T, GpuError>;

/// Adapts a `vk::Result` error into a [`GpuError`] that says what was being done.
pub(crate) fn vk_err(what: &str) -> impl FnOnce(vk::Result) -> GpuError + '_ {
    move |result| GpuError::Vulkan {
        what: what.to_string(),
        result,
    }
}
