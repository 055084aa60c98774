//! Reflective shadow maps (Dachsbacher & Stamminger 2005): per light view, the world position,
//! normal and reflected flux of what the light sees, one layer per shadow view of the scene.

use ash::vk;

use super::bindings as ids;
use crate::gi::FrameContext;
use crate::gpu::{
    Binding, Depth, Draw, Gpu, GpuResult, Image, ImageDesc, RasterPass, RasterPipeline,
    RasterPipelineDesc, Recorder,
};
use crate::render::targets::check_layered_image;
use crate::scene::Scene;
use crate::shader_shared::{RASTER_MATERIALS, RASTER_TRIANGLES, RASTER_VERTICES};
use crate::shaders;

crate::push_constants! {
    struct RsmPush {
        view_projection: [[f32; 4]; 4],
        light_position: [f32; 4],
        view: u32,
        size: u32,
    }
}

/// The RSM of every shadow view: layered position, normal and flux images.
pub struct Rsm {
    pipeline: RasterPipeline,
    /// Texels along each side of a layer.
    pub size: u32,
    /// Layers (shadow views: one per spot light, six per point light; at least one).
    pub layers: u32,
    pub position: Image,
    pub normal: Image,
    pub flux: Image,
    depth: Image,
}

impl Rsm {
    pub fn new(gpu: &Gpu, scene: &Scene, size: u32) -> anyhow::Result<Rsm> {
        let pipeline = RasterPipeline::new(
            gpu,
            &RasterPipelineDesc {
                name: "rsm",
                vertex: shaders::GI_SHARED_RSM_VERT,
                fragment: Some(shaders::GI_SHARED_RSM_FRAG),
                color_formats: &[
                    vk::Format::R32G32B32A32_SFLOAT,
                    vk::Format::R16G16B16A16_SFLOAT,
                    vk::Format::R32G32B32A32_SFLOAT,
                ],
                depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                depth_bias: None,
                additive_blend: false,
                conservative: false,
                specialization: &crate::scene::gpu::texture_specialization(scene),
            },
        )?;
        let lights = scene.raster_lights();
        let layers = crate::scene::light::shadow_view_total(&lights);
        // Position and flux are 16 bytes a texel, the normal 8.
        check_layered_image(
            gpu,
            &format!("the reflective shadow map of {} light(s)", lights.len()),
            (size, layers, 16),
            "use fewer lights or a smaller --rsm",
        )?;
        let layered = |name, format| {
            gpu.create_image(&ImageDesc {
                layers,
                array: true,
                ..ImageDesc::new_2d(
                    name,
                    format,
                    size,
                    size,
                    // Transfer source: tests read the VPLs back.
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::STORAGE
                        | vk::ImageUsageFlags::TRANSFER_SRC,
                )
            })
        };
        Ok(Rsm {
            pipeline,
            size,
            layers,
            position: layered("rsm position", vk::Format::R32G32B32A32_SFLOAT)?,
            normal: layered("rsm normal", vk::Format::R16G16B16A16_SFLOAT)?,
            flux: layered("rsm flux", vk::Format::R32G32B32A32_SFLOAT)?,
            depth: gpu.create_image(&ImageDesc::new_2d(
                "rsm depth",
                vk::Format::D32_SFLOAT,
                size,
                size,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            ))?,
        })
    }

    /// Render every shadow view's layer ("rsm view N").
    pub fn record(&self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        let s = ctx.scene;
        for (view, matrix) in s.shadow_view_matrices.iter().enumerate() {
            let push = RsmPush {
                view_projection: matrix.to_cols_array_2d(),
                light_position: s.shadow_view_origins[view].extend(1.0).to_array(),
                view: view as u32,
                size: self.size,
            };
            let layer = view as u32;
            rec.in_layer(layer, |rec| {
                rec.raster(&RasterPass {
                    name: "rsm",
                    pipeline: &self.pipeline,
                    bindings: &[
                        Binding::read(RASTER_VERTICES, &s.vertices),
                        Binding::read(RASTER_TRIANGLES, &s.triangles),
                        Binding::read(RASTER_MATERIALS, &s.materials),
                        Binding::read(ids::RSM_LIGHTS, &s.lights),
                        Binding::read(ids::RSM_VIEWS, &s.shadow_views),
                        Binding::read(ids::RSM_TEXTURES, &s.textures),
                    ],
                    push: &push,
                    color: &[
                        (&self.position, layer, [0.0; 4]),
                        (&self.normal, layer, [0.0; 4]),
                        (&self.flux, layer, [0.0; 4]),
                    ],
                    depth: Some((&self.depth, 0)),
                    draw: Draw::Vertices(s.vertex_count),
                    keep_contents: false,
                })
            })?;
        }
        Ok(())
    }
}
