//! Per-pixel passes as fragment shaders over one full-screen triangle
//! (shaders-glsl/common/fullscreen.vert), each writing or adding to one render target. On
//! lavapipe a render target's write (and its blend) costs a fraction of a compute pass's
//! imageStore (and imageLoad) of the same pixel: docs/performance.md, "Writing shaders for lavapipe".

use ash::vk;

use super::targets::GBUFFER_DEPTH_FORMAT;
use crate::gpu::{Depth, Gpu, GpuResult, RasterPipeline, RasterPipelineDesc, Specialization};
use crate::shaders;

/// What the fragment's output does to the render target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blend {
    /// It replaces the pixel.
    Replace,
    /// It is added to the pixel (one plus one).
    Add,
}

/// Which pixels a per-pixel pass shades.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pixels {
    /// Every pixel of the render target.
    All,
    /// Only the pixels a surface covers: the pass is drawn with the view's G-buffer depth as its
    /// depth attachment ([`Depth::Covered`]), and background pixels keep what the render target
    /// held (its clear value, or what an earlier pass wrote). On lavapipe the early depth test
    /// skips the SIMD batches of background pixels before the shader runs.
    Covered,
}

/// The pipeline of a per-pixel pass named `name`: `fragment` (a fragment shader that reads
/// its pixel at `gl_FragCoord.xy`) into one render target of `format`. Draw it with
/// `Draw::Vertices(3)`, at `pixels`.
pub fn full_screen(
    gpu: &Gpu,
    name: &str,
    fragment: &[u8],
    (format, pixels): (vk::Format, Pixels),
    blend: Blend,
    specialization: &Specialization,
) -> GpuResult<RasterPipeline> {
    let shaders = FullScreenShaders {
        vertex: shaders::COMMON_FULLSCREEN_VERT,
        fragment,
    };
    full_screen_with(gpu, name, shaders, (format, pixels), blend, specialization)
}

/// A per-pixel pass's shaders: the full-screen triangle's vertex shader (common/fullscreen.vert,
/// or one that also hands the fragments data every pixel shares as flat varyings: a fragment
/// shader reads push constants and buffers lane by lane on lavapipe) and the fragment shader.
#[derive(Clone, Copy)]
pub struct FullScreenShaders<'a> {
    pub vertex: &'a [u8],
    pub fragment: &'a [u8],
}

/// [`full_screen`] with a vertex shader of its own.
pub fn full_screen_with(
    gpu: &Gpu,
    name: &str,
    shaders: FullScreenShaders,
    (format, pixels): (vk::Format, Pixels),
    blend: Blend,
    specialization: &Specialization,
) -> GpuResult<RasterPipeline> {
    RasterPipeline::new(
        gpu,
        &RasterPipelineDesc {
            name,
            vertex: shaders.vertex,
            fragment: Some(shaders.fragment),
            color_formats: &[format],
            depth: match pixels {
                Pixels::All => None,
                Pixels::Covered => Some(Depth::Covered(GBUFFER_DEPTH_FORMAT)),
            },
            depth_bias: None,
            additive_blend: blend == Blend::Add,
            conservative: false,
            specialization,
        },
    )
}
