//! THE frame, top to bottom, written once ([`Frame::record_order`]): moved lights, shadow maps
//! and every view's G-buffer -> the GI method's per-view work and light work -> its
//! independent parts -> per view: direct lighting, the GI lookup, tone mapping. One submitter
//! runs that order as one command buffer, or split across queues (the parts each on a compute
//! queue, joined by timeline semaphores).
//!
//! A frame has one or more views (the walls of a CAVE): each has its own eye, G-buffer and
//! images, while shadows and the GI light are computed once per frame and shared by all views.

use ash::vk;

use super::part_ledger::PartLedger;
use super::passes::ScenePasses;
use super::targets::{Eye, View, check_buffer, check_image_size, check_layered_image};
use crate::error::InputError;
use crate::gi::{Changes, FrameContext, GiMethod};
use crate::gpu::frames::{FrameBuilder, FrameRing, SemaphoreWait, TimelineSemaphore};
use crate::gpu::{
    Gpu, GpuError, GpuResult, Image, ImageDesc, Part, Recorder, Sampler, ScopeTag, Stage,
};
use crate::scene::gpu::{GpuVertex, SceneBuffers};
use crate::scene::{Light, Scene};

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrameOptions {
    pub width: u32,
    pub height: u32,
    /// Exposure in stops applied before tone mapping.
    pub exposure_ev: f32,
    /// Side of each shadow-map layer in texels.
    pub shadow_map_size: u32,
    /// Leave direct light and emission out of the HDR image (to score indirect light alone).
    pub indirect_only: bool,
    pub submit: SubmitPlan,
    /// Treat the lights as moved in every frame: every frame redoes the work that depends on
    /// them (shadow maps, and a method's RSMs and injection), which a frame whose lights and
    /// geometry did not change otherwise keeps. Profiles and reports measure that frame.
    #[serde(default)]
    pub lights_move: bool,
    /// Draw a GI method's lookup as a pass of its own after direct lighting, even where the
    /// method can draw it inside direct lighting (`GiMethod::record_lit_lookup`), e.g. to time
    /// the two apart. The image is the same.
    #[serde(default)]
    pub lookup_apart: bool,
}

impl Default for FrameOptions {
    fn default() -> Self {
        FrameOptions {
            width: 640,
            height: 480,
            exposure_ev: 0.0,
            shadow_map_size: 1024,
            indirect_only: false,
            submit: SubmitPlan::Auto,
            lights_move: false,
            lookup_apart: false,
        }
    }
}

/// How a frame submits a GI method's independent parts.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
pub enum SubmitPlan {
    /// Async when the device has at least two compute queues to run parts on at once, else
    /// sequential.
    Auto,
    /// One command buffer on the graphics queue: the parts run one after another.
    Sequential,
    /// One submission per part on its compute queue, joined with timeline semaphores. On a
    /// device with one queue the submissions still go through the semaphores, in sequence.
    Async,
}

/// Work the frame's last submission does after tone mapping (e.g. showing the views in a
/// window), with the semaphores it waits on and signals.
pub struct Epilogue<'a> {
    pub waits: &'a [SemaphoreWait],
    pub signals: &'a [(vk::Semaphore, u64)],
    pub record: &'a dyn Fn(&mut Recorder, &Frame) -> GpuResult<()>,
}

/// Timeline semaphores of the async plan: "light work done" and "part p done".
struct PartSync {
    light_ready: TimelineSemaphore,
    part_done: Vec<TimelineSemaphore>,
    next: u64,
}

pub struct Frame {
    pub options: FrameOptions,
    pub scene: SceneBuffers,
    passes: ScenePasses,
    pub shadow_map: Image,
    pub shadow_sampler: Sampler,
    pub views: Vec<View>,
    /// The lights as they are now (moved by [`Frame::set_lights`]).
    lights: Vec<Light>,
    /// The lights the rasteriser draws (the scene's, then its area-light samples).
    raster_lights: Vec<Light>,
    /// Light and shadow-view records to write into the scene buffers at the next frame.
    pending_lights: Option<(Vec<u8>, Vec<u8>)>,
    /// Vertex records (byte offset, bytes) to write into the vertex buffer at the next frame.
    pending_vertices: Vec<(u64, Vec<u8>)>,
    /// What changed since the last recorded frame (everything before the first).
    changes: Changes,
    /// The shadow maps hold the lights and geometry as they are (drawn again when they change).
    shadows_drawn: bool,
    /// Frames recorded since the GI method began (see [`Frame::restart_method`]).
    frames_recorded: u64,
    asynchronous: bool,
    part_sync: Option<PartSync>,
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
        let raster_lights = scene.raster_lights();
        let shadow_layers = crate::scene::light::shadow_view_total(&raster_lights);
        check_layered_image(
            gpu,
            &format!("the shadow map of {} light(s)", raster_lights.len()),
            (options.shadow_map_size, shadow_layers, 4),
            "use fewer lights or a smaller --shadow-map",
        )?;
        let mesh = &scene.mesh;
        check_buffer(
            gpu,
            &format!("the vertex buffer of {} vertices", mesh.positions.len()),
            mesh.positions.len() as u64 * std::mem::size_of::<GpuVertex>() as u64,
        )?;
        check_buffer(
            gpu,
            &format!("the triangle buffer of {} triangles", mesh.triangle_count()),
            mesh.triangle_count() as u64 * 16,
        )?;
        let scene_buffers =
            SceneBuffers::upload(gpu, scene, &raster_lights, options.shadow_map_size)?;
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
        let asynchronous = match options.submit {
            SubmitPlan::Auto => gpu.queues.runs_parts_concurrently(),
            SubmitPlan::Sequential => false,
            SubmitPlan::Async => true,
        };
        let mut frame = Frame {
            passes: ScenePasses::new(gpu, scene, &raster_lights)?,
            scene: scene_buffers,
            shadow_map,
            shadow_sampler: gpu
                .create_sampler(vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?,
            views: Vec::new(),
            lights: scene.lights.clone(),
            raster_lights,
            pending_lights: None,
            pending_vertices: Vec::new(),
            changes: Changes::ALL,
            shadows_drawn: false,
            frames_recorded: 0,
            asynchronous,
            part_sync: None,
            options,
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
            self.views.push(View::new(gpu, width, height, eye)?);
        }
        self.changes.views = true;
        Ok(())
    }

    /// Move the views' eyes (as many eyes as views).
    pub fn set_eyes(&mut self, eyes: &[Eye]) {
        for (view, &eye) in self.views.iter_mut().zip(eyes) {
            if view.eye != eye {
                view.eye = eye;
                self.changes.camera = true;
            }
        }
    }

    /// Take the scene's lights as they are now (moved or turned); the next recorded frame
    /// writes them into the light buffers before anything reads them. The lights' kinds must
    /// be those the frame was made with.
    pub fn set_lights(&mut self, scene: &Scene) {
        self.raster_lights = scene.raster_lights();
        let (lights, views) = crate::scene::gpu::shadow_views(
            scene,
            &self.raster_lights,
            self.options.shadow_map_size,
        );
        self.scene.set_shadow_views(&views);
        self.lights = scene.lights.clone();
        self.pending_lights = Some((
            bytemuck::cast_slice(&lights).to_vec(),
            bytemuck::cast_slice(&views).to_vec(),
        ));
        self.changes.lights = true;
    }

    /// Take the scene's vertices `range` as they are now (an emitter or a dynamic object moved,
    /// see [`crate::scene::movable`] and [`crate::scene::dynamic`]); the next recorded frame
    /// writes them before anything reads them. For an emitter call [`Frame::set_lights`] too:
    /// the area-light samples move with it.
    pub fn set_vertices(&mut self, scene: &Scene, range: std::ops::Range<u32>) {
        let vertices: Vec<GpuVertex> = range
            .clone()
            .map(|i| GpuVertex::of(&scene.mesh, i as usize))
            .collect();
        let offset = u64::from(range.start) * std::mem::size_of::<GpuVertex>() as u64;
        self.pending_vertices
            .push((offset, bytemuck::cast_slice(&vertices).to_vec()));
        self.changes.geometry = true;
    }

    /// A GI method new to this frame (built again, or another) records the next frame: it is
    /// its first (`FrameContext::frame` 0, everything changed).
    pub fn restart_method(&mut self) {
        self.frames_recorded = 0;
        self.changes = Changes::ALL;
    }

    /// How the frame's direct lighting runs (its form, where its lights are read).
    pub fn direct_lighting(&self) -> String {
        self.passes.describe_direct_lighting()
    }

    /// How the frame's tone mapping runs (its form).
    pub fn tone_map(&self) -> String {
        self.passes.describe_tone_map()
    }

    /// How this frame submits a method's parts (after resolving `SubmitPlan::Auto`).
    pub fn submit_plan(&self) -> SubmitPlan {
        if self.asynchronous {
            SubmitPlan::Async
        } else {
            SubmitPlan::Sequential
        }
    }

    /// THE frame's order, recorded through `segments` (one command buffer, or submissions
    /// across queues). The epilogue, if any, ends the last segment.
    fn record_order(
        &mut self,
        segments: &mut dyn Segments,
        mut gi: Option<&mut dyn GiMethod>,
        epilogue: Option<&Epilogue>,
    ) -> GpuResult<()> {
        let pending = self.pending_lights.take();
        let pending_vertices = std::mem::take(&mut self.pending_vertices);
        let mut changes = std::mem::take(&mut self.changes);
        changes.lights |= self.options.lights_move;
        // The shadow maps depend on the lights and the geometry alone.
        let shadows = changes.lights || changes.geometry || !self.shadows_drawn;
        self.shadows_drawn = true;
        let frame = &*self;
        let ctx = FrameContext {
            scene: &frame.scene,
            shadow_map: &frame.shadow_map,
            shadow_sampler: &frame.shadow_sampler,
            views: &frame.views,
            lights: &frame.lights,
            raster_lights: &frame.raster_lights,
            frame: frame.frames_recorded,
            changes,
            lights_move: frame.options.lights_move,
            indirect_only: frame.options.indirect_only,
        };
        let method = gi.as_ref().map(|g| g.name());
        let tag = |stage: Stage, view: Option<usize>| ScopeTag {
            method: if matches!(stage, Stage::Scene | Stage::Direct | Stage::Output) {
                None
            } else {
                method
            },
            stage,
            view: view.map(|v| v as u32),
            ..ScopeTag::default()
        };
        segments.head(&mut |rec| {
            rec.set_context(tag(Stage::Scene, None));
            rec.update_buffer_runs("update vertices", &frame.scene.vertices, &pending_vertices);
            if let Some((lights, views)) = &pending {
                rec.update_buffer("update lights", &frame.scene.lights, lights);
                rec.update_buffer("update shadow views", &frame.scene.shadow_views, views);
            }
            if shadows {
                frame
                    .passes
                    .record_shadows(rec, &frame.scene, &frame.shadow_map)?;
            }
            for (v, view) in frame.views.iter().enumerate() {
                rec.set_context(tag(Stage::Scene, Some(v)));
                frame.passes.record_gbuffer(rec, &frame.scene, view)?;
            }
            if let Some(gi) = gi.as_deref_mut() {
                for v in 0..frame.views.len() {
                    rec.set_context(tag(Stage::GiView, Some(v)));
                    gi.record_view(rec, &ctx, v)?;
                }
                rec.set_context(tag(Stage::GiLight, None));
                gi.record_light(rec, &ctx)?;
            }
            Ok(())
        })?;
        if let Some(gi) = gi.as_deref_mut() {
            let labels = gi.parts();
            if !labels.is_empty() {
                let mut ledger = PartLedger::default();
                segments.parts(labels.len(), &mut |rec, part| {
                    rec.set_context(ScopeTag {
                        part: Some(Part {
                            index: part as u32,
                            label: labels[part],
                        }),
                        ..tag(Stage::GiPart, None)
                    });
                    gi.record_part(rec, &ctx, part)?;
                    ledger.add(labels, part, &rec.take_part_uses())
                })?;
            }
            gi.light_done(&ctx);
        }
        segments.tail(&mut |rec| {
            let shadows = (&frame.shadow_map, &frame.shadow_sampler);
            let include_direct = !frame.options.indirect_only;
            for (v, view) in frame.views.iter().enumerate() {
                // Direct lighting with the method's lookup in one pass, where it can.
                let lit = match gi.as_deref() {
                    Some(gi) if !frame.options.lookup_apart => {
                        let direct =
                            frame
                                .passes
                                .direct_draw(&frame.scene, shadows, view, include_direct);
                        rec.set_context(tag(Stage::GiLookup, Some(v)));
                        match direct {
                            Some(direct) => gi.record_lit_lookup(rec, &ctx, v, &direct)?,
                            None => false,
                        }
                    }
                    _ => false,
                };
                if !lit {
                    rec.set_context(tag(Stage::Direct, Some(v)));
                    frame.passes.record_direct_lighting(
                        rec,
                        &frame.scene,
                        shadows,
                        view,
                        include_direct,
                    )?;
                    if let Some(gi) = gi.as_deref() {
                        rec.set_context(tag(Stage::GiLookup, Some(v)));
                        gi.record_lookup(rec, &ctx, v)?;
                    }
                }
                rec.set_context(tag(Stage::Output, Some(v)));
                frame
                    .passes
                    .record_tonemap(rec, view, frame.options.exposure_ev)?;
            }
            if let Some(e) = epilogue {
                rec.set_context(tag(Stage::Output, None));
                (e.record)(rec, frame)?;
            }
            Ok(())
        })?;
        self.frames_recorded += 1;
        Ok(())
    }

    /// The whole frame into one command buffer, in order, with a GI method's passes if there
    /// is one (its parts one after another, once however many views there are).
    pub fn record(&mut self, rec: &mut Recorder, gi: Option<&mut dyn GiMethod>) -> GpuResult<()> {
        self.record_order(&mut Inline { rec }, gi, None)
    }

    /// Record and submit one frame (see [`Frame::submit_frame`]).
    pub fn submit(
        &mut self,
        gpu: &Gpu,
        ring: &mut FrameRing,
        gi: Option<&mut dyn GiMethod>,
    ) -> GpuResult<()> {
        let builder = ring.begin_frame()?;
        self.submit_frame(gpu, builder, gi, None)
    }

    /// Record and submit a begun frame. With the async plan and a method with parts, the frame
    /// is 2 + parts submissions: the head (scene, the method's view and light work) on the
    /// graphics queue; each part on its compute queue once the head is done; the tail (every
    /// view's direct light, lookup and tone mapping) on the graphics queue once every part is
    /// done. Otherwise it is one command buffer on the graphics queue. The epilogue, if any,
    /// ends the last submission. After an error, neither the frame nor the method may record
    /// again: their resources' tracked states name accesses of a recording never submitted.
    pub fn submit_frame(
        &mut self,
        gpu: &Gpu,
        builder: FrameBuilder,
        gi: Option<&mut dyn GiMethod>,
        epilogue: Option<&Epilogue>,
    ) -> GpuResult<()> {
        let (waits, signals) = epilogue.map_or((&[][..], &[][..]), |e| (e.waits, e.signals));
        let parts = gi.as_ref().map_or(0, |g| g.parts().len());
        if !self.asynchronous || parts == 0 {
            return builder.finish(gpu, &gpu.queues.graphics, waits, signals, |rec| {
                self.record_order(&mut Inline { rec }, gi, epilogue)
            });
        }
        let mut sync = match self.part_sync.take() {
            Some(sync) => sync,
            None => PartSync {
                light_ready: TimelineSemaphore::new(gpu, 0)?,
                part_done: Vec::new(),
                next: 0,
            },
        };
        while sync.part_done.len() < parts {
            sync.part_done.push(TimelineSemaphore::new(gpu, 0)?);
        }
        sync.next += 1;
        let result = {
            let mut split = Split {
                gpu,
                builder: Some(builder),
                sync: &sync,
                value: sync.next,
                parts: 0,
                last_waits: waits,
                last_signals: signals,
            };
            self.record_order(&mut split, gi, epilogue)
        };
        self.part_sync = Some(sync);
        result
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
        self.read_view_ldr(gpu, 0)
    }

    /// A view's tone-mapped sRGB output, RGBA8 per pixel.
    pub fn read_view_ldr(&self, gpu: &Gpu, view: usize) -> GpuResult<Vec<u8>> {
        gpu.read_image(&self.views[view].ldr)
    }

    /// The first view's G-buffer world positions (w = 0 for background), for tests and masks.
    pub fn read_positions(&self, gpu: &Gpu) -> GpuResult<Vec<[f32; 4]>> {
        let bytes = gpu.read_image(&self.view().gbuffer.position)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec())
    }
}

/// Where the frame's order goes: the head (graphics), the parts, the tail (graphics).
trait Segments {
    fn head(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()>;
    fn parts(
        &mut self,
        count: usize,
        record: &mut dyn FnMut(&mut Recorder, usize) -> GpuResult<()>,
    ) -> GpuResult<()>;
    fn tail(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()>;
}

/// Everything into one command buffer, in order.
struct Inline<'r, 'a> {
    rec: &'r mut Recorder<'a>,
}

impl Segments for Inline<'_, '_> {
    fn head(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()> {
        record(self.rec)
    }

    fn parts(
        &mut self,
        count: usize,
        record: &mut dyn FnMut(&mut Recorder, usize) -> GpuResult<()>,
    ) -> GpuResult<()> {
        (0..count).try_for_each(|part| record(self.rec, part))
    }

    fn tail(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()> {
        record(self.rec)
    }
}

/// One submission for the head, one per part on its compute queue, one for the tail.
struct Split<'f, 'g> {
    gpu: &'g Gpu,
    builder: Option<FrameBuilder<'f>>,
    sync: &'g PartSync,
    /// This frame's value of the timeline semaphores.
    value: u64,
    parts: usize,
    last_waits: &'g [SemaphoreWait],
    last_signals: &'g [(vk::Semaphore, u64)],
}

/// The error of a segment submitted after the frame's last one (a bug in the order).
fn finished() -> GpuError {
    GpuError::Setup("a frame segment came after the frame was finished".into())
}

impl<'f> Split<'f, '_> {
    fn builder(&mut self) -> GpuResult<&mut FrameBuilder<'f>> {
        self.builder.as_mut().ok_or_else(finished)
    }

    fn after(&self, semaphore: &TimelineSemaphore) -> SemaphoreWait {
        SemaphoreWait {
            semaphore: semaphore.raw,
            value: self.value,
            stage: vk::PipelineStageFlags2::ALL_COMMANDS,
        }
    }
}

impl Segments for Split<'_, '_> {
    fn head(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()> {
        let signal = [(self.sync.light_ready.raw, self.value)];
        let gpu = self.gpu;
        self.builder()?
            .submit(gpu, &gpu.queues.graphics, &[], &signal, |rec| record(rec))
    }

    fn parts(
        &mut self,
        count: usize,
        record: &mut dyn FnMut(&mut Recorder, usize) -> GpuResult<()>,
    ) -> GpuResult<()> {
        let wait = [self.after(&self.sync.light_ready)];
        let gpu = self.gpu;
        for part in 0..count {
            let signal = [(self.sync.part_done[part].raw, self.value)];
            let queue = gpu.queues.part_queue(part);
            self.builder()?
                .submit(gpu, &queue, &wait, &signal, |rec| record(rec, part))?;
        }
        self.parts = count;
        Ok(())
    }

    fn tail(&mut self, record: &mut dyn FnMut(&mut Recorder) -> GpuResult<()>) -> GpuResult<()> {
        let mut waits: Vec<SemaphoreWait> = self.sync.part_done[..self.parts]
            .iter()
            .map(|s| self.after(s))
            .collect();
        waits.extend_from_slice(self.last_waits);
        let gpu = self.gpu;
        match self.builder.take() {
            Some(b) => b.finish(
                gpu,
                &gpu.queues.graphics,
                &waits,
                self.last_signals,
                |rec| record(rec),
            ),
            None => Err(finished()),
        }
    }
}
