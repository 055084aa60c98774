//! THE frame, top to bottom: shadow maps -> G-buffer -> GI light (RSM, injection, propagation)
//! -> direct lighting -> GI lookup -> tone mapping. Every pass of a raster frame is recorded
//! here, in order; a GI technique (src/gi/) adds its passes at the two marked points.
//!
//! A frame has one or more views (the walls of a CAVE): each has its own eye, G-buffer and
//! images, while shadows and the GI light are computed once per frame and shared by all views.

use std::cell::{Cell, RefCell};

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::error::InputError;
use crate::gi::Technique;
use crate::gpu::frames::{FrameBuilder, FrameRing, SemaphoreWait, TimelineSemaphore};
use crate::gpu::{
    Binding, ComputePass, ComputePipeline, Gpu, GpuResult, Image, ImageDesc, RasterPass,
    RasterPipeline, RasterPipelineDesc, Recorder, Sampler, Specialization,
};
use crate::scene::gpu::SceneBuffers;
use crate::scene::{Camera, Scene};
use crate::shader_shared as ids;
use crate::shaders;

/// Largest image side vkgi renders (also bounded by the device's limit).
pub const MAX_IMAGE_SIDE: u32 = 8192;

#[derive(Clone, Debug)]
pub struct FrameOptions {
    pub width: u32,
    pub height: u32,
    /// Exposure in stops applied before tone mapping.
    pub exposure_ev: f32,
    /// Side of each shadow-map layer in texels.
    pub shadow_map_size: u32,
    /// Leave direct light and emission out of the HDR image (to score indirect light alone).
    pub indirect_only: bool,
    pub channel_plan: ChannelPlan,
}

impl Default for FrameOptions {
    fn default() -> Self {
        FrameOptions {
            width: 640,
            height: 480,
            exposure_ev: 0.0,
            shadow_map_size: 1024,
            indirect_only: false,
            channel_plan: ChannelPlan::Auto,
        }
    }
}

/// The attachments the G-buffer pass writes and lighting passes read.
pub struct GBuffer {
    /// xyz world position, w = 1 where a surface was hit, 0 for background.
    pub position: Image,
    /// xyz unit normal facing the camera.
    pub normal: Image,
    pub albedo: Image,
    pub emission: Image,
    pub depth: Image,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GBufferPush {
    view_projection: [[f32; 4]; 4],
    camera_position: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LightingPush {
    size: [u32; 2],
    light_count: u32,
    include_direct: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct TonemapPush {
    size: [u32; 2],
    exposure_scale: f32,
}

/// Where a view looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// World to clip space (Vulkan: depth 0..1, y down).
    pub view_projection: Mat4,
    pub position: Vec3,
}

impl Eye {
    /// The eye of a pinhole camera for an image of `width` x `height`, with clip planes that
    /// enclose the scene.
    pub fn from_camera(camera: &Camera, scene: &Scene, width: u32, height: u32) -> Eye {
        let aspect = width as f32 / height.max(1) as f32;
        Eye {
            view_projection: camera.view_projection(aspect, scene.bounds_min, scene.bounds_max),
            position: camera.position,
        }
    }
}

/// One view of the frame: its eye, G-buffer and output images.
pub struct View {
    pub eye: Eye,
    pub gbuffer: GBuffer,
    /// Linear HDR radiance (the image every error metric is computed on).
    pub hdr: Image,
    /// Tone-mapped, sRGB-encoded 8-bit output.
    pub ldr: Image,
}

impl View {
    pub fn width(&self) -> u32 {
        self.hdr.width()
    }
    pub fn height(&self) -> u32 {
        self.hdr.height()
    }
}

/// Work the frame's last submission does after tone mapping (e.g. showing the views in a
/// window), with the semaphores it waits on and signals.
pub struct Epilogue<'a> {
    pub waits: &'a [SemaphoreWait],
    pub signals: &'a [(vk::Semaphore, u64)],
    pub record: &'a dyn Fn(&mut Recorder, &Frame) -> GpuResult<()>,
}

pub struct Frame {
    pub options: FrameOptions,
    pub scene: SceneBuffers,
    shadow_pipeline: RasterPipeline,
    gbuffer_pipeline: RasterPipeline,
    lighting_pipeline: ComputePipeline,
    tonemap_pipeline: ComputePipeline,
    pub shadow_map: Image,
    pub shadow_sampler: Sampler,
    pub views: Vec<View>,
    /// Light and shadow-view records to write into the scene buffers at the next frame.
    pending_lights: RefCell<Option<(Vec<u8>, Vec<u8>)>>,
    /// Semaphores joining the per-channel submissions (async plan only).
    channel_sync: Option<ChannelSync>,
}

/// How a frame submits a GI technique's colour-channel work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum ChannelPlan {
    /// Async when the device has three compute queues for the channels, else sequential.
    Auto,
    /// One command buffer on the graphics queue: the channels run one after another.
    Sequential,
    /// One submission per channel on its compute queue, joined with timeline semaphores. On a
    /// device with one queue the submissions still go through the semaphores, in sequence.
    Async,
}

/// Timeline semaphores of the async channel plan: "light injected" and "channel c done".
struct ChannelSync {
    light_ready: TimelineSemaphore,
    channel_done: [TimelineSemaphore; 3],
    next: Cell<u64>,
}

/// Formats of the G-buffer's colour attachments: position, normal, albedo, emission.
const GBUFFER_FORMATS: [vk::Format; 4] = [
    vk::Format::R32G32B32A32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
];

/// A view's G-buffer and images.
fn create_view(gpu: &Gpu, width: u32, height: u32, eye: Eye) -> GpuResult<View> {
    let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT
        | vk::ImageUsageFlags::STORAGE
        | vk::ImageUsageFlags::TRANSFER_SRC;
    let image = |name: &str, format: vk::Format, usage: vk::ImageUsageFlags| {
        gpu.create_image(&ImageDesc::new_2d(name, format, width, height, usage))
    };
    let gbuffer = GBuffer {
        position: image("g-buffer position", GBUFFER_FORMATS[0], attachment)?,
        normal: image("g-buffer normal", GBUFFER_FORMATS[1], attachment)?,
        albedo: image("g-buffer albedo", GBUFFER_FORMATS[2], attachment)?,
        emission: image("g-buffer emission", GBUFFER_FORMATS[3], attachment)?,
        depth: image(
            "g-buffer depth",
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        )?,
    };
    let storage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
    Ok(View {
        eye,
        gbuffer,
        hdr: image("hdr radiance", vk::Format::R32G32B32A32_SFLOAT, storage)?,
        ldr: image("ldr output", vk::Format::R8G8B8A8_UNORM, storage)?,
    })
}

/// Check an image size against vkgi's and the device's limits.
pub fn check_image_size(gpu: &Gpu, width: u32, height: u32) -> Result<(), InputError> {
    let limit = MAX_IMAGE_SIDE.min(gpu.info.max_image_dimension_2d);
    if width == 0 || height == 0 || width > limit || height > limit {
        return Err(InputError::new(format!(
            "image size {width}x{height} is out of range: each side must be 1..={limit}"
        )));
    }
    Ok(())
}

impl Frame {
    /// A frame of one view, from the scene's camera.
    pub fn new(gpu: &Gpu, scene: &Scene, options: FrameOptions) -> anyhow::Result<Frame> {
        let eye = Eye::from_camera(&scene.camera, scene, options.width, options.height);
        Frame::with_eyes(gpu, scene, options, &[eye])
    }

    /// A frame of one view per eye, each `options.width` x `options.height`.
    pub fn with_eyes(
        gpu: &Gpu,
        scene: &Scene,
        options: FrameOptions,
        eyes: &[Eye],
    ) -> anyhow::Result<Frame> {
        check_image_size(gpu, options.width, options.height)?;
        let shadow_limit = 8192.min(gpu.info.max_image_dimension_2d);
        if !(16..=shadow_limit).contains(&options.shadow_map_size) {
            return Err(InputError::new(format!(
                "shadow map size {} is out of range 16..={shadow_limit}",
                options.shadow_map_size
            ))
            .into());
        }
        if !options.exposure_ev.is_finite() || options.exposure_ev.abs() > 64.0 {
            return Err(InputError::new(format!(
                "exposure {} EV is out of range -64..=64",
                options.exposure_ev
            ))
            .into());
        }
        let scene_buffers = SceneBuffers::upload(gpu, scene, options.shadow_map_size)?;

        let shadow_pipeline = RasterPipeline::new(
            gpu,
            &RasterPipelineDesc {
                name: "shadow map",
                vertex: shaders::RASTER_SHADOW_VERT,
                fragment: None,
                color_formats: &[],
                depth_format: Some(vk::Format::D32_SFLOAT),
                depth_bias: Some((1.25, 1.75)),
            },
        )?;
        let gbuffer_pipeline = RasterPipeline::new(
            gpu,
            &RasterPipelineDesc {
                name: "g-buffer",
                vertex: shaders::RASTER_GBUFFER_VERT,
                fragment: Some(shaders::RASTER_GBUFFER_FRAG),
                color_formats: &GBUFFER_FORMATS,
                depth_format: Some(vk::Format::D32_SFLOAT),
                depth_bias: None,
            },
        )?;
        let none = Specialization::new();
        let lighting_pipeline =
            ComputePipeline::new(gpu, "direct lighting", shaders::RASTER_LIGHTING_COMP, &none)?;
        let tonemap_pipeline =
            ComputePipeline::new(gpu, "tone map", shaders::RASTER_TONEMAP_COMP, &none)?;

        let shadow_layers = scene_buffers.shadow_view_matrices.len().max(1) as u32;
        let shadow_map = gpu.create_image(&ImageDesc {
            layers: shadow_layers,
            array: true,
            ..ImageDesc::new_2d(
                "shadow map",
                vk::Format::D32_SFLOAT,
                options.shadow_map_size,
                options.shadow_map_size,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            )
        })?;
        let shadow_sampler =
            gpu.create_sampler(vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let asynchronous = match options.channel_plan {
            ChannelPlan::Auto => gpu.queues.has_async_channels(),
            ChannelPlan::Sequential => false,
            ChannelPlan::Async => true,
        };
        let channel_sync = if asynchronous {
            Some(ChannelSync {
                light_ready: TimelineSemaphore::new(gpu, 0)?,
                channel_done: [
                    TimelineSemaphore::new(gpu, 0)?,
                    TimelineSemaphore::new(gpu, 0)?,
                    TimelineSemaphore::new(gpu, 0)?,
                ],
                next: Cell::new(0),
            })
        } else {
            None
        };
        let mut frame = Frame {
            channel_sync,
            options,
            scene: scene_buffers,
            shadow_pipeline,
            gbuffer_pipeline,
            lighting_pipeline,
            tonemap_pipeline,
            shadow_map,
            shadow_sampler,
            views: Vec::new(),
            pending_lights: RefCell::new(None),
        };
        let (w, h) = (frame.options.width, frame.options.height);
        frame.resize(gpu, w, h, eyes)?;
        Ok(frame)
    }

    /// New views of `width` x `height`, one per eye (a window's new size, or another CAVE).
    /// No submitted frame may still use the old views (wait for the device first).
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32, eyes: &[Eye]) -> GpuResult<()> {
        self.views.clear();
        self.options.width = width;
        self.options.height = height;
        for &eye in eyes {
            let view = create_view(gpu, width, height, eye)?;
            self.views.push(view);
        }
        Ok(())
    }

    /// Move the views' eyes (as many eyes as views).
    pub fn set_eyes(&mut self, eyes: &[Eye]) {
        for (view, &eye) in self.views.iter_mut().zip(eyes) {
            view.eye = eye;
        }
    }

    /// Take the scene's lights as they are now (moved or turned); the next recorded frame
    /// writes them into the light buffers before anything reads them. The lights' kinds must
    /// be those the frame was made with.
    pub fn set_lights(&mut self, scene: &Scene) {
        let (lights, views) = crate::scene::gpu::shadow_views(scene, self.options.shadow_map_size);
        self.scene.set_shadow_views(scene, &views);
        *self.pending_lights.borrow_mut() = Some((
            bytemuck::cast_slice(&lights).to_vec(),
            bytemuck::cast_slice(&views).to_vec(),
        ));
    }

    /// Write moved lights into the scene's light buffers (when there are any).
    fn record_light_update(&self, rec: &mut Recorder) {
        if let Some((lights, views)) = self.pending_lights.borrow_mut().take() {
            rec.update_buffer("update lights", &self.scene.lights, &lights);
            rec.update_buffer("update shadow views", &self.scene.shadow_views, &views);
        }
    }

    /// Shadow maps: one depth layer per shadow view.
    pub fn record_shadows(&self, rec: &mut Recorder) -> GpuResult<()> {
        for (layer, view_projection) in self.scene.shadow_view_matrices.iter().enumerate() {
            let push = view_projection.to_cols_array_2d();
            rec.raster(&RasterPass {
                name: "shadow map",
                pipeline: &self.shadow_pipeline,
                bindings: &[Binding::read(ids::RASTER_VERTICES, &self.scene.vertices)],
                push: bytemuck::bytes_of(&push),
                color: &[],
                depth: Some((&self.shadow_map, layer as u32)),
                vertex_count: self.scene.vertex_count,
            })?;
        }
        Ok(())
    }

    /// A view's G-buffer from its eye.
    pub fn record_gbuffer(&self, rec: &mut Recorder, view: &View) -> GpuResult<()> {
        let push = GBufferPush {
            view_projection: view.eye.view_projection.to_cols_array_2d(),
            camera_position: view.eye.position.extend(1.0).to_array(),
        };
        let g = &view.gbuffer;
        rec.raster(&RasterPass {
            name: "g-buffer",
            pipeline: &self.gbuffer_pipeline,
            bindings: &[
                Binding::read(ids::RASTER_VERTICES, &self.scene.vertices),
                Binding::read(
                    ids::RASTER_TRIANGLE_MATERIALS,
                    &self.scene.triangle_materials,
                ),
                Binding::read(ids::RASTER_MATERIALS, &self.scene.materials),
            ],
            push: bytemuck::bytes_of(&push),
            color: &[
                (&g.position, 0, [0.0; 4]),
                (&g.normal, 0, [0.0; 4]),
                (&g.albedo, 0, [0.0; 4]),
                (&g.emission, 0, [0.0; 4]),
            ],
            depth: Some((&g.depth, 0)),
            vertex_count: self.scene.vertex_count,
        })
    }

    /// Direct light (and emission) into a view's HDR image.
    pub fn record_direct_lighting(&self, rec: &mut Recorder, view: &View) -> GpuResult<()> {
        let g = &view.gbuffer;
        let push = LightingPush {
            size: [view.width(), view.height()],
            light_count: self.scene.light_count,
            include_direct: u32::from(!self.options.indirect_only),
        };
        rec.compute(&ComputePass {
            name: "direct lighting",
            pipeline: &self.lighting_pipeline,
            bindings: &[
                Binding::image_read(ids::LIGHTING_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::LIGHTING_GBUFFER_NORMAL, &g.normal),
                Binding::image_read(ids::LIGHTING_GBUFFER_ALBEDO, &g.albedo),
                Binding::image_read(ids::LIGHTING_GBUFFER_EMISSION, &g.emission),
                Binding::sampled(
                    ids::LIGHTING_SHADOW_MAP,
                    &self.shadow_map,
                    &self.shadow_sampler,
                ),
                Binding::read(ids::LIGHTING_LIGHTS, &self.scene.lights),
                Binding::read(ids::LIGHTING_SHADOW_VIEWS, &self.scene.shadow_views),
                Binding::image_write(ids::LIGHTING_HDR_OUT, &view.hdr),
            ],
            push: bytemuck::bytes_of(&push),
            threads: [view.width(), view.height(), 1],
        })
    }

    /// Exposure, tone mapping and sRGB encoding into a view's 8-bit output.
    pub fn record_tonemap(&self, rec: &mut Recorder, view: &View) -> GpuResult<()> {
        let push = TonemapPush {
            size: [view.width(), view.height()],
            exposure_scale: self.options.exposure_ev.exp2(),
        };
        rec.compute(&ComputePass {
            name: "tone map",
            pipeline: &self.tonemap_pipeline,
            bindings: &[
                Binding::image_read(ids::TONEMAP_HDR_IN, &view.hdr),
                Binding::image_write(ids::TONEMAP_LDR_OUT, &view.ldr),
            ],
            push: bytemuck::bytes_of(&push),
            threads: [view.width(), view.height(), 1],
        })
    }

    /// What comes before the GI light: moved lights, shadow maps, every view's G-buffer.
    fn record_geometry(&self, rec: &mut Recorder) -> GpuResult<()> {
        self.record_light_update(rec);
        self.record_shadows(rec)?;
        for view in &self.views {
            self.record_gbuffer(rec, view)?;
        }
        Ok(())
    }

    /// What comes after the GI light, per view: direct light, the GI lookup, tone mapping.
    fn record_views(&self, rec: &mut Recorder, gi: Option<&dyn Technique>) -> GpuResult<()> {
        for view in &self.views {
            self.record_direct_lighting(rec, view)?;
            if let Some(gi) = gi {
                gi.record_lookup(rec, view)?;
            }
            self.record_tonemap(rec, view)?;
        }
        Ok(())
    }

    /// The whole frame in one command buffer, in order, with a GI technique's passes if there
    /// is one (its colour channels one after another, once however many views there are).
    pub fn record(&self, rec: &mut Recorder, mut gi: Option<&mut dyn Technique>) -> GpuResult<()> {
        self.record_geometry(rec)?;
        if let Some(gi) = gi.as_deref_mut() {
            gi.record_light(rec, self)?;
            for channel in 0..3 {
                gi.record_channel(rec, channel)?;
            }
            gi.light_recorded();
        }
        self.record_views(rec, gi.as_deref())
    }

    /// Record and submit one frame (see [`Frame::submit_frame`]).
    pub fn submit(
        &self,
        gpu: &Gpu,
        ring: &mut FrameRing,
        gi: Option<&mut dyn Technique>,
    ) -> GpuResult<()> {
        let builder = ring.begin_frame()?;
        self.submit_frame(gpu, builder, gi, None)
    }

    /// Record and submit a begun frame. With the async channel plan and a technique, the frame
    /// is five submissions: shadows, G-buffers and the technique's light on the graphics queue;
    /// each colour channel on its compute queue once that is done; then direct lighting, the
    /// lookup and tone mapping of every view on the graphics queue once all three channels are
    /// done, joined by timeline semaphores. Otherwise it is one command buffer on the graphics
    /// queue. The epilogue, if any, ends the last submission.
    pub fn submit_frame(
        &self,
        gpu: &Gpu,
        mut frame: FrameBuilder,
        gi: Option<&mut dyn Technique>,
        epilogue: Option<&Epilogue>,
    ) -> GpuResult<()> {
        let graphics = gpu.queues.graphics;
        let (last_waits, signals) = epilogue.map_or((&[][..], &[][..]), |e| (e.waits, e.signals));
        let finish = |rec: &mut Recorder| match epilogue {
            Some(e) => (e.record)(rec, self),
            None => Ok(()),
        };
        let (gi, sync) = match (gi, &self.channel_sync) {
            (Some(gi), Some(sync)) => (gi, sync),
            (gi, _) => {
                return frame.finish(gpu, &graphics, last_waits, signals, |rec| {
                    self.record(rec, gi)?;
                    finish(rec)
                });
            }
        };
        let value = sync.next.get() + 1;
        sync.next.set(value);
        let after = |s: &TimelineSemaphore| SemaphoreWait {
            semaphore: s.raw,
            value,
            stage: vk::PipelineStageFlags2::ALL_COMMANDS,
        };
        frame.submit(
            gpu,
            &graphics,
            &[],
            &[(sync.light_ready.raw, value)],
            |rec| {
                self.record_geometry(rec)?;
                gi.record_light(rec, self)
            },
        )?;
        for (channel, done) in sync.channel_done.iter().enumerate() {
            let queue = gpu.queues.channel_compute[channel];
            frame.submit(
                gpu,
                &queue,
                &[after(&sync.light_ready)],
                &[(done.raw, value)],
                |rec| gi.record_channel(rec, channel),
            )?;
        }
        gi.light_recorded();
        let mut waits: Vec<SemaphoreWait> = sync.channel_done.iter().map(after).collect();
        waits.extend_from_slice(last_waits);
        frame.finish(gpu, &graphics, &waits, signals, |rec| {
            self.record_views(rec, Some(&*gi))?;
            finish(rec)
        })
    }

    /// How this frame submits colour channels (after resolving `ChannelPlan::Auto`).
    pub fn channel_plan(&self) -> ChannelPlan {
        if self.channel_sync.is_some() {
            ChannelPlan::Async
        } else {
            ChannelPlan::Sequential
        }
    }

    /// The first view (the only one outside a CAVE).
    pub fn view(&self) -> &View {
        &self.views[0]
    }

    /// The first view's linear HDR radiance, RGB per pixel, row-major from the top-left.
    pub fn read_hdr(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 3]>> {
        self.read_view_hdr(gpu, 0)
    }

    /// A view's linear HDR radiance, RGB per pixel, row-major from the top-left.
    pub fn read_view_hdr(&self, gpu: &Gpu, view: usize) -> GpuResult<Vec<[f32; 3]>> {
        let bytes = gpu.read_image(&self.views[view].hdr)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
            .iter()
            .map(|p| [p[0], p[1], p[2]])
            .collect())
    }

    /// The first view's tone-mapped sRGB output, RGBA8 per pixel.
    pub fn read_ldr(&self, gpu: &Gpu) -> GpuResult<Vec<u8>> {
        gpu.read_image(&self.view().ldr)
    }

    /// The first view's G-buffer world positions (w = 0 for background), for tests and masks.
    pub fn read_positions(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 4]>> {
        let bytes = gpu.read_image(&self.view().gbuffer.position)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec())
    }
}
