//! A CAVE process's window. A render node's shows its wall (one eye, or a stereo pair side by
//! side, top-bottom or as a red-cyan anaglyph) with an overlay of the run's sync figures; the
//! master's shows its overlay alone and takes the keyboard and mouse. Both loops wait on the
//! network, so winit's events are pumped between frames rather than driving them.

use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::platform::pump_events::EventLoopExtPumpEvents;
use winit::raw_window_handle::{HasDisplayHandle, RawDisplayHandle};
use winit::window::{Window, WindowId};

use super::stereo::StereoLayout;
use crate::gi::GiMethod;
use crate::gpu::frames::{FrameBuilder, FrameRing, SemaphoreWait};
use crate::gpu::swapchain::Acquired;
use crate::gpu::{Binding, ComputePass, ComputePipeline, Gpu, Specialization};
use crate::render::{Epilogue, Frame};
use crate::shader_shared as ids;
use crate::shaders;
use crate::view::drag::Drag;
use crate::view::output::{Output, Tile};
use crate::view::overlay::Overlay;

crate::push_constants! {
    struct AnaglyphPush {
        origin: [i32; 2],
        tile: [i32; 2],
        view_size: [i32; 2],
    }
}

/// Creates the window when winit is ready, and notes what happens to it.
struct Events {
    attributes: winit::window::WindowAttributes,
    window: Option<Arc<Window>>,
    error: Option<winit::error::OsError>,
    closed: bool,
    resized: bool,
    /// Keys held down now.
    held: Vec<KeyCode>,
    /// Pointer travel while the left button was down since the last look, in pixels.
    dragged: (f32, f32),
    drag: Drag,
}

impl ApplicationHandler for Events {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            match event_loop.create_window(self.attributes.clone()) {
                Ok(window) => self.window = Some(Arc::new(window)),
                Err(e) => self.error = Some(e),
            }
        }
    }

    fn window_event(&mut self, _: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => self.closed = true,
            WindowEvent::Resized(_) => self.resized = true,
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.held.retain(|k| *k != code);
                    if event.state == ElementState::Pressed {
                        self.held.push(code);
                    }
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag.button(state == ElementState::Pressed);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x as f32, position.y as f32);
                if let Some((dx, dy)) = self.drag.moved_to(now) {
                    self.dragged.0 += dx;
                    self.dragged.1 += dy;
                }
            }
            _ => {}
        }
    }
}

/// The window before the GPU exists (the GPU needs its display).
pub struct Opened {
    event_loop: EventLoop<()>,
    events: Events,
    window: Arc<Window>,
}

impl Opened {
    /// Open a window titled `title` of `width` x `height`.
    pub fn new(title: &str, (width, height): (u32, u32)) -> anyhow::Result<Opened> {
        let mut event_loop = EventLoop::new().context(
            "a window needs a display (X11 or Wayland): give a node --headless, and the master no --window",
        )?;
        let mut events = Events {
            attributes: Window::default_attributes()
                .with_title(title)
                .with_inner_size(PhysicalSize::new(width, height)),
            window: None,
            error: None,
            closed: false,
            resized: false,
            held: Vec::new(),
            dragged: (0.0, 0.0),
            drag: Drag::default(),
        };
        for _ in 0..200 {
            event_loop.pump_app_events(Some(Duration::from_millis(10)), &mut events);
            if let Some(e) = events.error.take() {
                return Err(e).context("opening the node's window");
            }
            if let Some(window) = events.window.clone() {
                return Ok(Opened {
                    event_loop,
                    events,
                    window,
                });
            }
        }
        anyhow::bail!("the window system never let the node open its window")
    }

    pub fn display(&self) -> anyhow::Result<RawDisplayHandle> {
        Ok(self.event_loop.display_handle()?.as_raw())
    }
}

/// The window with its swapchain, overlay and (for an anaglyph) the pass that mixes the eyes.
pub struct Display {
    // Field order is drop order: GPU objects before the window and its event loop.
    anaglyph: Option<ComputePipeline>,
    overlay: Overlay,
    output: Output,
    layout: StereoLayout,
    views: usize,
    events: Events,
    event_loop: EventLoop<()>,
}

impl Display {
    pub fn new(
        gpu: &Gpu,
        opened: Opened,
        views: usize,
        layout: StereoLayout,
        frames_in_flight: usize,
    ) -> anyhow::Result<Display> {
        let anaglyph = (views == 2 && layout == StereoLayout::Anaglyph)
            .then(|| {
                ComputePipeline::new(
                    gpu,
                    "anaglyph",
                    shaders::VIEW_ANAGLYPH_COMP,
                    &Specialization::new(),
                )
            })
            .transpose()?;
        let mut display = Display {
            anaglyph,
            overlay: Overlay::new(gpu, frames_in_flight)?,
            output: Output::new(gpu, opened.window, false, frames_in_flight)?,
            layout,
            views,
            events: opened.events,
            event_loop: opened.event_loop,
        };
        display.place_tiles();
        Ok(display)
    }

    /// Handle the window's pending events; false once the user closed it.
    pub fn pump(&mut self) -> bool {
        self.event_loop
            .pump_app_events(Some(Duration::ZERO), &mut self.events);
        !self.events.closed
    }

    /// The keys held down now.
    pub fn held_keys(&self) -> &[KeyCode] {
        &self.events.held
    }

    /// How far the pointer was dragged (left button) since the last call, in pixels.
    pub fn take_drag(&mut self) -> (f32, f32) {
        std::mem::take(&mut self.events.dragged)
    }

    /// Show `lines` alone (the master's window: no views).
    pub fn show_text(
        &mut self,
        gpu: &Gpu,
        ring: &mut FrameRing,
        lines: &[String],
    ) -> anyhow::Result<()> {
        let (builder, acquired) = self.begin(gpu, ring)?;
        let slot = builder.slot();
        let Some(acquired) = acquired else {
            return Ok(builder.finish(gpu, &gpu.queues.graphics, &[], &[], |_| Ok(()))?);
        };
        self.overlay.set_text(slot, lines)?;
        let waits = [SemaphoreWait {
            semaphore: acquired.ready,
            value: 0,
            stage: vk::PipelineStageFlags2::BLIT | vk::PipelineStageFlags2::COMPUTE_SHADER,
        }];
        let (output, overlay) = (&self.output, &self.overlay);
        builder.finish(
            gpu,
            &gpu.queues.graphics,
            &waits,
            &[(acquired.rendered, 0)],
            |rec| {
                rec.clear_image("clear window", &output.composed, [0.05, 0.05, 0.08, 1.0]);
                overlay.record(rec, slot, &output.composed)?;
                output.record_present(rec, &acquired);
                Ok(())
            },
        )?;
        self.present(gpu, acquired)
    }

    /// Begin a frame: rebuild the swapchain if the window changed size (or presenting found it
    /// stale), then acquire an image (None when it is out of date: the frame is rendered but
    /// not shown, and the swapchain rebuilt for the next).
    fn begin<'r>(
        &mut self,
        gpu: &Gpu,
        ring: &'r mut FrameRing,
    ) -> anyhow::Result<(FrameBuilder<'r>, Option<Acquired>)> {
        let size = self.output.window.inner_size();
        if self.events.resized && size.width > 0 && size.height > 0 {
            self.events.resized = false;
            ring.finish()?;
            gpu.wait_idle()?;
            self.output.resize(gpu)?;
            self.place_tiles();
        }
        let builder = ring.begin_frame()?;
        let acquired = self.output.acquire(builder.slot())?;
        if acquired.is_none() {
            self.events.resized = true;
        }
        Ok((builder, acquired))
    }

    fn present(&mut self, gpu: &Gpu, acquired: Acquired) -> anyhow::Result<()> {
        let shown = crate::gpu::swapchain::Swapchain::present(
            &gpu.queues.graphics,
            &[(self.output.swapchain(), acquired)],
        )?;
        if !shown {
            self.events.resized = true;
        }
        Ok(())
    }

    /// Render `frame` and show it with `lines` over it. The GI method's state advances exactly
    /// as without a window: a frame whose swapchain is out of date is rendered all the same,
    /// only not shown (the swapchain is rebuilt for the next).
    pub fn render(
        &mut self,
        gpu: &Gpu,
        ring: &mut FrameRing,
        frame: &mut Frame,
        gi: Option<&mut dyn GiMethod>,
        lines: &[String],
    ) -> anyhow::Result<()> {
        let (builder, acquired) = self.begin(gpu, ring)?;
        let slot = builder.slot();
        let Some(acquired) = acquired else {
            return Ok(frame.submit_frame(gpu, builder, gi, None)?);
        };
        self.overlay.set_text(slot, lines)?;
        let waits = [SemaphoreWait {
            semaphore: acquired.ready,
            value: 0,
            stage: vk::PipelineStageFlags2::BLIT | vk::PipelineStageFlags2::COMPUTE_SHADER,
        }];
        let signals = [(acquired.rendered, 0)];
        let (output, overlay, anaglyph) = (&self.output, &self.overlay, &self.anaglyph);
        let record = |rec: &mut crate::gpu::Recorder, frame: &Frame| {
            output.record_compose(rec, frame);
            if let Some(pipeline) = anaglyph {
                // The pair fills the first tile (inside the window: see `place_tiles`).
                let rect = output.tiles[0].rect;
                let view = &frame.views[0];
                rec.compute(&ComputePass {
                    name: "anaglyph",
                    pipeline,
                    bindings: &[
                        Binding::image_read(ids::ANAGLYPH_LEFT, &frame.views[0].ldr),
                        Binding::image_read(ids::ANAGLYPH_RIGHT, &frame.views[1].ldr),
                        Binding::image_write(ids::ANAGLYPH_TARGET, &output.composed),
                    ],
                    push: &AnaglyphPush {
                        origin: [rect[0], rect[1]],
                        tile: [rect[2], rect[3]],
                        view_size: [view.width() as i32, view.height() as i32],
                    },
                    threads: [rect[2] as u32, rect[3] as u32, 1],
                })?;
            }
            overlay.record(rec, slot, &output.composed)?;
            output.record_present(rec, &acquired);
            Ok(())
        };
        let epilogue = Epilogue {
            waits: &waits,
            signals: &signals,
            record: &record,
        };
        frame.submit_frame(gpu, builder, gi, Some(&epilogue))?;
        self.present(gpu, acquired)
    }

    /// The window image of the last frame (views, anaglyph and overlay), RGBA8, and its size.
    pub fn read_window(&self, gpu: &Gpu) -> anyhow::Result<(Vec<u8>, (u32, u32))> {
        let image = &self.output.composed;
        Ok((gpu.read_image(image)?, (image.width(), image.height())))
    }

    /// Views (square, of the frame's side) centred in the window: one, or a pair laid out.
    fn place_tiles(&mut self) {
        let (w, h) = self.output.size();
        let (w, h) = (w as i32, h as i32);
        let fit = |columns: i32, rows: i32| (w / columns).min(h / rows).max(1);
        let tiles = match (self.views, self.layout) {
            (2, StereoLayout::SideBySide) => {
                let side = fit(2, 1);
                let (x, y) = ((w - 2 * side) / 2, (h - side) / 2);
                vec![[x, y, side, side], [x + side, y, side, side]]
            }
            (2, StereoLayout::TopBottom) => {
                let side = fit(1, 2);
                let (x, y) = ((w - side) / 2, (h - 2 * side) / 2);
                vec![[x, y, side, side], [x, y + side, side, side]]
            }
            _ => {
                let side = fit(1, 1);
                vec![[(w - side) / 2, (h - side) / 2, side, side]]
            }
        };
        // The anaglyph mixes its two views into the first tile: only the left is blitted.
        self.output.tiles = tiles
            .into_iter()
            .enumerate()
            .map(|(view, rect)| Tile { view, rect })
            .collect();
    }
}
