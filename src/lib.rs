//! vkgi: real-time global illumination on raw Vulkan, measured against a reference path tracer.

pub mod app;
pub mod cave;
pub mod digest;
pub mod error;
pub mod font;
pub mod gi;
pub mod gpu;
pub mod imageio;
pub mod metrics;
pub mod reference;
pub mod render;
pub mod scene;
pub mod shader_shared;
pub mod view;

/// The SPIR-V of every shader under shaders-glsl/, compiled by build.rs.
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}
