//! Per-view images of the triangle each pixel sees (index + 1, 0 for none), drawn with the
//! G-buffer's geometry, for methods that store their light per triangle or per patch and look
//! it up per pixel (LightWave's per-vertex gather, radiosity's elements).

use ash::vk;

use crate::gi::FrameContext;
use crate::gpu::{
    Binding, Depth, Draw, Gpu, GpuResult, Image, ImageDesc, RasterPass, RasterPipeline,
    RasterPipelineDesc, Recorder,
};
use crate::render::targets::View;
use crate::shader_shared::{RASTER_TRIANGLES, RASTER_VERTICES};
use crate::shaders;

crate::push_constants! {
    struct TriangleIdsPush {
        view_projection: [[f32; 4]; 4],
    }
}

/// One view's triangle image and the depth it is drawn with.
struct ViewIds {
    ids: Image,
    depth: Image,
}

pub struct TriangleIds {
    name: &'static str,
    pipeline: RasterPipeline,
    /// Per view, made (again) when the view's size changes.
    views: Vec<ViewIds>,
}

impl TriangleIds {
    /// `name` labels the pass and the images (e.g. "lightwave triangle ids").
    pub fn new(gpu: &Gpu, name: &'static str) -> GpuResult<TriangleIds> {
        Ok(TriangleIds {
            name,
            pipeline: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name,
                    vertex: shaders::GI_SHARED_TRIANGLE_IDS_VERT,
                    fragment: Some(shaders::GI_SHARED_TRIANGLE_IDS_FRAG),
                    color_formats: &[vk::Format::R32_UINT],
                    depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                    depth_bias: None,
                    additive_blend: false,
                    conservative: false,
                    specialization: &crate::gpu::Specialization::new(),
                },
            )?,
            views: Vec::new(),
        })
    }

    /// Draw the triangle each pixel of view `index` sees (after [`TriangleIds::fit_views`]).
    pub fn record_view(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        index: usize,
    ) -> GpuResult<()> {
        let view = &ctx.views[index];
        let targets = &self.views[index];
        rec.raster(&RasterPass {
            name: self.name,
            pipeline: &self.pipeline,
            bindings: &[
                Binding::read(RASTER_VERTICES, &ctx.scene.vertices),
                Binding::read(RASTER_TRIANGLES, &ctx.scene.triangles),
            ],
            push: &TriangleIdsPush {
                view_projection: view.eye.view_projection.to_cols_array_2d(),
            },
            color: &[(&targets.ids, 0, [0.0; 4])],
            depth: Some((&targets.depth, 0)),
            draw: Draw::Vertices(ctx.scene.vertex_count),
            keep_contents: false,
        })
    }

    /// View `index`'s triangle image (R32_UINT).
    pub fn image(&self, index: usize) -> &Image {
        &self.views[index].ids
    }

    /// An image per view, of the view's size (made again when the views change).
    pub fn fit_views(&mut self, gpu: &Gpu, views: &[View]) -> GpuResult<()> {
        let fits = |t: &ViewIds, v: &View| {
            (t.ids.extent.width, t.ids.extent.height) == (v.width(), v.height())
        };
        if self.views.len() == views.len() && self.views.iter().zip(views).all(|(t, v)| fits(t, v))
        {
            return Ok(());
        }
        // Images of the old size may still be in flight.
        gpu.wait_idle()?;
        self.views = views
            .iter()
            .map(|v| {
                let image = |format, usage| {
                    gpu.create_image(&ImageDesc::new_2d(
                        self.name,
                        format,
                        v.width(),
                        v.height(),
                        usage,
                    ))
                };
                Ok(ViewIds {
                    ids: image(
                        vk::Format::R32_UINT,
                        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
                    )?,
                    depth: image(
                        vk::Format::D32_SFLOAT,
                        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                    )?,
                })
            })
            .collect::<GpuResult<_>>()?;
        Ok(())
    }
}
