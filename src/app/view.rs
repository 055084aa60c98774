//! `vkgi view`: the windowed renderer. winit's event loop drives the frame: input moves the
//! camera and the light, keys switch the GI method and its settings, each redraw renders every
//! view (one, or the walls of a CAVE) with one shared GI light and presents them.

use std::collections::{HashSet, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context;
use ash::vk;
use glam::Vec3;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::raw_window_handle::HasDisplayHandle;
use winit::window::{Window, WindowId};

use crate::cave::Pose;
use crate::cave::path::TrackedPath;
use crate::gi::GiMethod;
use crate::gi::registry::{self, MethodEntry};
use crate::gi::settings::{Setting, Settings};
use crate::gpu::frames::{FrameRing, SemaphoreWait};
use crate::gpu::{Gpu, GpuOptions, Stage};
use crate::imageio::HdrImage;
use crate::render::runner::{self, FRAMES_IN_FLIGHT};
use crate::render::{Epilogue, Eye, Frame};
use crate::scene::Scene;
use crate::scene::movable::Movable;
use crate::view::cave::Cave;
use crate::view::drag::Drag;
use crate::view::fly::FlyCamera;
use crate::view::keys;
use crate::view::output::{Output, cave_tiles};
use crate::view::overlay::Overlay;

use super::cli::ViewArgs;
use super::{method, output};

/// Frames the overlay's per-pass times average over.
const OVERLAY_FRAMES: u64 = 16;
/// Passes the overlay lists (the costliest, after the frame total).
const OVERLAY_PASSES: usize = 8;
/// Profiler samples kept before old ones are dropped, unless the profile is being recorded.
const MAX_LIVE_SAMPLES: usize = 20_000;

/// The viewer's own keys, for F1 (a method's setting keys follow them).
const HELP: &[&str] = &[
    "W A S D  MOVE    Q E  DOWN/UP    DRAG  TURN    WHEEL  SPEED",
    "ARROWS  MOVE THE LIGHT    PAGE UP/DOWN  LIGHT UP/DOWN    L  NEXT LIGHT OR EMITTER",
    "J K  DIM/BRIGHTEN THE LIGHT    T  TINT    Z X  TURN THE SPOT    R F  TILT THE SPOT",
    "I  INDIRECT ONLY    O  DIRECT ONLY    P  SCREENSHOT (PNG + EXR)    F1  HELP    ESC  QUIT",
];

/// The key of a character a method's settings may use (punctuation, letters, digits).
pub fn key_of(c: char) -> Option<KeyCode> {
    let code = match c {
        '[' => KeyCode::BracketLeft,
        ']' => KeyCode::BracketRight,
        ',' => KeyCode::Comma,
        '.' => KeyCode::Period,
        '-' => KeyCode::Minus,
        '=' => KeyCode::Equal,
        ';' => KeyCode::Semicolon,
        '\'' => KeyCode::Quote,
        '/' => KeyCode::Slash,
        c => return super::cli::parse_key(&c.to_string()).ok(),
    };
    Some(code)
}

/// The setting of `settings` that `code` steps, and in which direction (+1 or -1).
fn setting_key(settings: &Settings, code: KeyCode) -> Option<(&'static Setting, f64)> {
    settings.specs().iter().find_map(|s| {
        let keys = s.keys?;
        if key_of(keys.increase) == Some(code) {
            Some((s, 1.0))
        } else if key_of(keys.decrease) == Some(code) {
            Some((s, -1.0))
        } else {
            None
        }
    })
}

pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    let mut scene = Scene::load(&args.scene)?;
    scene.area_samples = args.frame.area_samples;
    log::info!("{}", scene.statistics());
    if args.frames == Some(0) {
        crate::bad_input!("--frames must be at least 1");
    }
    crate::view::cave::check_size(args.cave_size)?;
    let tracked = args.path.as_deref().map(TrackedPath::load).transpose()?;
    if let Some(path) = &tracked {
        path.check_scene(&scene)?;
    }
    let (width, height) = args.frame.size;
    let limit = crate::render::MAX_IMAGE_SIDE;
    if width == 0 || height == 0 || width > limit || height > limit {
        crate::bad_input!(
            "window size {width}x{height} is out of range: each side must be 1..={limit}"
        );
    }
    let event_loop = EventLoop::new().context(
        "opening a window needs a display (X11 or Wayland); without one use `vkgi render`",
    )?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = ViewApp {
        args: args.clone(),
        scene: Some(scene),
        tracked,
        running: None,
        error: None,
    };
    event_loop.run_app(&mut app)?;
    if let Some(error) = app.error {
        return Err(error);
    }
    Ok(())
}

struct ViewApp {
    args: ViewArgs,
    /// The scene until the window opens (then it moves into `running`).
    scene: Option<Scene>,
    /// `--path`'s samples until the window opens.
    tracked: Option<TrackedPath>,
    running: Option<Running>,
    error: Option<anyhow::Error>,
}

impl ViewApp {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.error.get_or_insert(error);
        self.close(event_loop);
    }

    /// Finish every frame, destroy everything, and check that the validation layers saw no
    /// error up to the destruction of the instance.
    fn close(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(mut running) = self.running.take() {
            if let Err(e) = running.shut_down(&self.args) {
                self.error.get_or_insert(e);
            }
            let log = running.gpu.shared_validation_log();
            drop(running);
            let errors = log.map_or(0, |l| l.error_count());
            if errors > 0 {
                self.error.get_or_insert(anyhow::anyhow!(
                    "the Vulkan validation layers reported {errors} error(s) (logged above)"
                ));
            }
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for ViewApp {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(scene) = self.scene.take() else {
            return;
        };
        match Running::new(event_loop, &self.args, scene, self.tracked.take()) {
            Ok(running) => self.running = Some(running),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, id: WindowId, event: WindowEvent) {
        let Some(running) = self.running.as_mut() else {
            return;
        };
        let result = match event {
            WindowEvent::CloseRequested => {
                self.close(event_loop);
                return;
            }
            WindowEvent::Resized(_) => {
                running.resize_pending = true;
                Ok(Flow::Continue)
            }
            WindowEvent::RedrawRequested if running.outputs[0].window.id() == id => {
                running.redraw(&self.args)
            }
            WindowEvent::KeyboardInput { event, .. } => running.key(&event),
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                running.drag.button(state == ElementState::Pressed);
                Ok(Flow::Continue)
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x as f32, position.y as f32);
                if let Some((dx, dy)) = running.drag.moved_to(now) {
                    running.fly.turn(dx, dy);
                }
                Ok(Flow::Continue)
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                running.fly.scroll(steps);
                Ok(Flow::Continue)
            }
            _ => Ok(Flow::Continue),
        };
        match result {
            Ok(Flow::Continue) => {}
            Ok(Flow::Close) => self.close(event_loop),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            // A minimised window sleeps until an event (its restoring resize) wakes it.
            if running.minimised() {
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::Poll);
                running.outputs[0].window.request_redraw();
            }
        }
    }
}

enum Flow {
    Continue,
    Close,
}

/// Everything that lives while the window is open. Field order is drop order: GPU objects
/// before the GPU.
struct Running {
    outputs: Vec<Output>,
    overlay: Overlay,
    technique: Option<Box<dyn GiMethod>>,
    frame: Frame,
    ring: FrameRing,
    gpu: Gpu,
    scene: Scene,
    fly: FlyCamera,
    cave: Option<Cave>,
    /// `--path`: the tracked samples, and the pose last applied from them.
    tracked: Option<TrackedPath>,
    pose: Option<Pose>,
    /// The method shown (None: direct light only).
    method: Option<&'static MethodEntry>,
    /// Every registered method's settings (the user's flags applied), kept across switches.
    settings: Vec<Settings>,
    /// What the overlay says about the last settings change (e.g. a rejected lattice size).
    status: String,
    held: HashSet<KeyCode>,
    /// What the arrow keys move (punctual lights, then emitters), and which of them.
    movables: Vec<Movable>,
    moving: usize,
    /// An emitter moved since the GI method was made: it is made again once the keys let go
    /// (its set-up reads the geometry).
    geometry_moved: bool,
    drag: Drag,
    resize_pending: bool,
    help: bool,
    direct_only: bool,
    last_redraw: Instant,
    frame_seconds: VecDeque<f32>,
    frames_shown: u64,
    screenshots: u32,
    /// The whole profile is wanted at the end (so samples are never dropped).
    recording_profile: bool,
}

impl Running {
    fn new(
        event_loop: &ActiveEventLoop,
        args: &ViewArgs,
        scene: Scene,
        tracked: Option<TrackedPath>,
    ) -> anyhow::Result<Self> {
        let (width, height) = args.frame.size;
        let windows = if args.cave_windows { 4 } else { 1 };
        let mut handles = Vec::new();
        for index in 0..windows {
            let title = if args.cave_windows {
                format!("vkgi: {} (CAVE wall {})", scene.name, index + 1)
            } else {
                format!("vkgi: {}", scene.name)
            };
            let attributes = Window::default_attributes()
                .with_title(title)
                .with_inner_size(PhysicalSize::new(width, height));
            handles.push(Arc::new(event_loop.create_window(attributes)?));
        }
        let display = event_loop.display_handle()?.as_raw();
        let gpu = Gpu::new(&GpuOptions {
            display: Some(display),
            ..args.gpu.options()
        })
        .context("setting up the GPU")?;
        let mut outputs = Vec::new();
        for window in handles {
            outputs.push(Output::new(&gpu, window, !args.no_vsync, FRAMES_IN_FLIGHT)?);
        }
        // The CAVE's viewer stands where the CAVE was placed, facing the camera's way; the
        // fly camera carries the CAVE from there.
        let (cave, fly) = if args.cave {
            let (cave, fly) = Cave::placed_with_fly(&scene, args.cave_size, args.head);
            (Some(cave), fly)
        } else {
            let extent = (scene.bounds_max - scene.bounds_min).length();
            (None, FlyCamera::new(scene.camera, extent))
        };
        let mut scene = scene;
        let movables = scene.movables();
        let frame = Frame::new(&gpu, &scene, args.frame.options())?;
        let overrides = &args.gi.settings.values;
        let chosen = method::choose(&args.gi.method, overrides)?;
        let settings = registry::methods()
            .map(|m| m.settings(overrides))
            .collect::<Result<Vec<_>, _>>()?;
        let mut ring = FrameRing::new(&gpu, FRAMES_IN_FLIGHT)?;
        ring.profiler
            .add_note(format!("queue plan: {}", gpu.queues.describe()));
        let overlay = Overlay::new(&gpu, FRAMES_IN_FLIGHT)?;
        let mut running = Running {
            outputs,
            overlay,
            technique: None,
            frame,
            ring,
            gpu,
            scene,
            fly,
            cave,
            tracked,
            pose: None,
            method: chosen.map(|c| c.entry),
            settings,
            status: String::new(),
            held: HashSet::new(),
            movables,
            moving: 0,
            geometry_moved: false,
            drag: Drag::default(),
            resize_pending: false,
            help: false,
            direct_only: false,
            last_redraw: Instant::now(),
            frame_seconds: VecDeque::new(),
            frames_shown: 0,
            screenshots: 0,
            recording_profile: args.profile.wanted(),
        };
        running.rebuild_technique()?;
        running.layout()?;
        Ok(running)
    }

    /// The index of the shown method in the registry (and in `settings`).
    fn method_index(&self) -> Option<usize> {
        let name = self.method?.name;
        registry::methods().position(|m| m.name == name)
    }

    /// Make the GI method for the current method and settings.
    fn rebuild_technique(&mut self) -> anyhow::Result<()> {
        self.ring.finish()?;
        self.gpu.wait_idle()?;
        self.technique = None;
        self.frame.restart_method();
        let (Some(entry), Some(index)) = (self.method, self.method_index()) else {
            return Ok(());
        };
        let chosen = method::Chosen {
            entry,
            settings: self.settings[index].clone(),
        };
        self.technique = Some(method::build(&self.gpu, &self.scene, &chosen, None)?);
        Ok(())
    }

    /// Try new settings of the shown method; keep the old ones (and say why) when the method
    /// rejects them.
    fn change_settings(&mut self, change: impl FnOnce(&mut Settings)) -> anyhow::Result<()> {
        let Some(index) = self.method_index() else {
            return self.rebuild_technique();
        };
        let previous = self.settings[index].clone();
        change(&mut self.settings[index]);
        match self.rebuild_technique() {
            Ok(()) => self.status.clear(),
            Err(e) if super::is_input_error(&e) => {
                self.status = format!("{e:#}").to_uppercase();
                self.settings[index] = previous;
                self.rebuild_technique()?;
            }
            Err(e) => return Err(e),
        }
        Ok(())
    }

    /// The next method of the cycle: none, then every registered method in order.
    fn next_method(&self) -> Option<&'static MethodEntry> {
        match self.method_index() {
            None => registry::methods().next(),
            Some(i) => registry::methods().nth(i + 1),
        }
    }

    /// Size the views to the windows and place them: the whole window, or the CAVE's walls.
    fn layout(&mut self) -> anyhow::Result<()> {
        self.ring.finish()?;
        self.gpu.wait_idle()?;
        for output in &mut self.outputs {
            output.resize(&self.gpu)?;
        }
        let (w, h) = self.outputs[0].size();
        let side = match self.cave {
            None => {
                self.outputs[0].tiles = vec![crate::view::output::Tile {
                    view: 0,
                    rect: [0, 0, w as i32, h as i32],
                }];
                let eyes = self.eyes(w, h);
                self.frame.resize(&self.gpu, w, h, &eyes)?;
                return Ok(());
            }
            Some(_) if self.outputs.len() > 1 => {
                for (view, output) in self.outputs.iter_mut().enumerate() {
                    let (ow, oh) = output.size();
                    output.tiles = vec![crate::view::output::Tile {
                        view,
                        rect: [0, 0, ow as i32, oh as i32],
                    }];
                }
                w.min(h)
            }
            Some(_) => {
                let (side, tiles) = cave_tiles(w, h);
                self.outputs[0].tiles = tiles;
                side
            }
        };
        let eyes = self.eyes(side, side);
        self.frame.resize(&self.gpu, side, side, &eyes)?;
        Ok(())
    }

    /// The eyes of every view for views of `w` x `h`.
    fn eyes(&mut self, w: u32, h: u32) -> Vec<Eye> {
        match &mut self.cave {
            None => vec![Eye::from_camera(&self.fly.camera, &self.scene, w, h)],
            Some(cave) => {
                cave.follow(&self.fly);
                cave.eyes(&self.scene)
            }
        }
    }

    fn key(&mut self, event: &KeyEvent) -> anyhow::Result<Flow> {
        let PhysicalKey::Code(code) = event.physical_key else {
            return Ok(Flow::Continue);
        };
        if event.state == ElementState::Released {
            self.held.remove(&code);
            return Ok(Flow::Continue);
        }
        if event.repeat {
            self.held.insert(code);
            return Ok(Flow::Continue);
        }
        self.press(code)
    }

    /// A key went down: remember it as held, and do what it does.
    fn press(&mut self, code: KeyCode) -> anyhow::Result<Flow> {
        self.held.insert(code);
        match code {
            KeyCode::Escape => return Ok(Flow::Close),
            KeyCode::F1 => self.help = !self.help,
            KeyCode::KeyP | KeyCode::F12 => {
                self.screenshots += 1;
                let prefix = PathBuf::from(format!("vkgi-screenshot-{}", self.screenshots));
                self.screenshot(&prefix)?;
                self.status = format!("SAVED {}", prefix.display()).to_uppercase();
            }
            KeyCode::KeyM => {
                self.method = self.next_method();
                self.change_settings(|_| {})?;
            }
            KeyCode::KeyI => {
                self.frame.options.indirect_only = !self.frame.options.indirect_only;
                self.direct_only = false;
            }
            KeyCode::KeyO => {
                self.direct_only = !self.direct_only;
                self.frame.options.indirect_only = false;
            }
            KeyCode::KeyL if !self.movables.is_empty() => {
                self.moving = (self.moving + 1) % self.movables.len();
            }
            KeyCode::KeyJ | KeyCode::KeyK | KeyCode::KeyT if !self.movables.is_empty() => {
                let which = self.movables[self.moving].clone();
                let changed = match code {
                    KeyCode::KeyJ => self.scene.dim(&which, 0.8),
                    KeyCode::KeyK => self.scene.dim(&which, 1.25),
                    _ => self.scene.retint(&which),
                };
                if changed {
                    self.frame.set_lights(&self.scene);
                } else {
                    self.status = "AN EMITTER ONLY MOVES (J K T ARE FOR LIGHTS)".into();
                }
            }
            code => {
                let keyed = self
                    .method_index()
                    .and_then(|i| setting_key(&self.settings[i], code));
                if let Some((setting, direction)) = keyed {
                    self.change_settings(|s| {
                        if let Some(value) = s.get(setting.name) {
                            let stepped = setting.stepped(value, direction);
                            s.set_value(setting.name, stepped);
                        }
                    })?;
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// Apply held keys for `seconds`: fly the camera, move the chosen light or emitter.
    fn apply_held_keys(&mut self, seconds: f32) -> anyhow::Result<()> {
        let held = |key: KeyCode| self.held.contains(&key);
        let axis = |plus, minus| keys::axis(&held, plus, minus);
        let travel = Vec3::new(
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::KeyE, KeyCode::KeyQ),
            axis(KeyCode::KeyW, KeyCode::KeyS),
        );
        self.fly.travel(travel, seconds);
        let light = keys::light_motion(&held);
        let Some(which) = self.movables.get(self.moving) else {
            return Ok(());
        };
        let (yaw, pitch) = (
            axis(KeyCode::KeyZ, KeyCode::KeyX),
            axis(KeyCode::KeyR, KeyCode::KeyF),
        );
        if (yaw, pitch) != (0.0, 0.0) && self.scene.aim(which, yaw * seconds, pitch * seconds) {
            self.frame.set_lights(&self.scene);
        }
        if light == Vec3::ZERO {
            if self.geometry_moved {
                self.geometry_moved = false;
                self.rebuild_technique()?;
                if let Some(entry) = self.method {
                    self.ring.profiler.add_note(format!(
                        "frame {}: {} made again around the moved emitter",
                        self.frames_shown, entry.name
                    ));
                }
            }
            return Ok(());
        }
        let step = light * 0.5 * self.fly.speed * seconds;
        self.scene.move_by(which, step);
        match which {
            Movable::Emitter { vertices, .. } => {
                self.frame.set_vertices(&self.scene, vertices.clone());
                self.geometry_moved = true;
                self.frame.set_lights(&self.scene);
            }
            Movable::Light(_) => self.frame.set_lights(&self.scene),
            // Posed with the next frame (see `pose_dynamic`).
            Movable::Object(_) => {}
        }
        Ok(())
    }

    /// Apply this frame's tracked sample (`--path`), as a CAVE master's node applies it.
    fn follow_path(&mut self) {
        let (Some(path), Some(cave)) = (&self.tracked, &mut self.cave) else {
            return;
        };
        let pose = path.at(self.frames_shown);
        let changes = crate::cave::updates(self.pose.as_ref(), &pose);
        crate::cave::apply(&changes, &mut self.scene, &mut self.frame, cave);
        self.pose = Some(pose);
    }

    /// Pose the dynamic objects for the frame about to be drawn (their paths, and the arrow
    /// keys' nudges) and let the frame and the GI method follow them (`runner::follow`: the
    /// method is made again where it cannot follow).
    fn pose_dynamic(&mut self) -> anyhow::Result<()> {
        let moved = self.scene.pose(self.frames_shown);
        let (entry, index) = (self.method, self.method_index());
        let (gpu, settings) = (&self.gpu, &self.settings);
        let rebuild = |scene: &Scene| match (entry, index) {
            (Some(entry), Some(index)) => {
                let chosen = method::Chosen {
                    entry,
                    settings: settings[index].clone(),
                };
                method::build(gpu, scene, &chosen, None)
            }
            _ => anyhow::bail!("no GI method to build"),
        };
        runner::follow(
            gpu,
            &mut self.ring,
            &mut self.frame,
            &self.scene,
            &moved,
            self.technique.as_mut(),
            &rebuild,
        )?;
        Ok(())
    }

    fn redraw(&mut self, args: &ViewArgs) -> anyhow::Result<Flow> {
        let now = Instant::now();
        let seconds = (now - self.last_redraw).as_secs_f32().min(0.25);
        self.last_redraw = now;
        let scripted = args.keys.get(self.frames_shown as usize).copied();
        if let Some(code) = scripted
            && let Flow::Close = self.press(code)?
        {
            return Ok(Flow::Close);
        }
        self.apply_held_keys(seconds)?;
        if let Some(code) = scripted {
            self.held.remove(&code);
        }
        self.follow_path();
        self.pose_dynamic()?;
        if self.minimised() {
            return Ok(Flow::Continue); // the swapchain is rebuilt once the window has an area
        }
        if self.resize_pending {
            self.resize_pending = false;
            self.layout()?;
        }
        let (w, h) = (self.frame.options.width, self.frame.options.height);
        let eyes = self.eyes(w, h);
        self.frame.set_eyes(&eyes);
        if !self.render()? {
            self.resize_pending = true;
            return Ok(Flow::Continue);
        }
        self.frames_shown += 1;
        self.frame_seconds.push_back(seconds);
        if self.frame_seconds.len() > 30 {
            self.frame_seconds.pop_front();
        }
        if let (Some(frames), Some((rw, rh))) = (args.frames, args.resize_to)
            && self.frames_shown == frames / 2
        {
            let _ = self.outputs[0]
                .window
                .request_inner_size(PhysicalSize::new(rw, rh));
        }
        match args.frames {
            Some(frames) if self.frames_shown >= frames => Ok(Flow::Close),
            _ => Ok(Flow::Continue),
        }
    }

    /// True while a window has no area (minimised): nothing is rendered.
    fn minimised(&self) -> bool {
        self.outputs.iter().any(|o| {
            let size = o.window.inner_size();
            size.width == 0 || size.height == 0
        })
    }

    /// Render and present one frame; false when a swapchain is out of date.
    fn render(&mut self) -> anyhow::Result<bool> {
        let lines = self.overlay_lines();
        let builder = self.ring.begin_frame()?;
        let slot = builder.slot();
        let mut acquired = Vec::new();
        for output in &self.outputs {
            match output.acquire(slot)? {
                Some(a) => acquired.push(a),
                None => return Ok(false),
            }
        }
        self.overlay.set_text(slot, &lines)?;
        let waits: Vec<SemaphoreWait> = acquired
            .iter()
            .map(|a| SemaphoreWait {
                semaphore: a.ready,
                value: 0,
                stage: vk::PipelineStageFlags2::BLIT,
            })
            .collect();
        let signals: Vec<(vk::Semaphore, u64)> = acquired.iter().map(|a| (a.rendered, 0)).collect();
        let (outputs, overlay) = (&self.outputs, &self.overlay);
        let record = |rec: &mut crate::gpu::Recorder, frame: &Frame| {
            for (index, (output, image)) in outputs.iter().zip(&acquired).enumerate() {
                output.record_compose(rec, frame);
                if index == 0 {
                    overlay.record(rec, slot, &output.composed)?;
                }
                output.record_present(rec, image);
            }
            Ok(())
        };
        let epilogue = Epilogue {
            waits: &waits,
            signals: &signals,
            record: &record,
        };
        let gi = match (&mut self.technique, self.direct_only) {
            (Some(t), false) => Some(t.as_mut() as &mut dyn GiMethod),
            _ => None,
        };
        self.frame
            .submit_frame(&self.gpu, builder, gi, Some(&epilogue))?;
        let presents: Vec<_> = outputs
            .iter()
            .map(|o| o.swapchain())
            .zip(acquired.iter().copied())
            .collect();
        let current =
            crate::gpu::swapchain::Swapchain::present(&self.gpu.queues.graphics, &presents)?;
        Ok(current)
    }

    /// The overlay: method and settings, frame rate, per-pass GPU milliseconds, help.
    fn overlay_lines(&mut self) -> Vec<String> {
        let method = match (self.method, self.method_index()) {
            (Some(entry), Some(i)) => {
                format!("{}  {}", entry.name, self.settings[i].keyed_summary()).to_uppercase()
            }
            _ => "DIRECT LIGHT ONLY (NO GI)".to_string(),
        };
        let mode = if self.direct_only {
            "  DIRECT ONLY"
        } else if self.frame.options.indirect_only {
            "  INDIRECT ONLY"
        } else {
            ""
        };
        let seconds: f32 =
            self.frame_seconds.iter().sum::<f32>() / self.frame_seconds.len().max(1) as f32;
        let fps = if seconds > 0.0 { 1.0 / seconds } else { 0.0 };
        let views = self.frame.views.len();
        let mut lines = vec![
            format!("{method}{mode}"),
            format!(
                "{fps:.1} FPS  {views} VIEW{}  {}X{}",
                if views == 1 { "" } else { "S" },
                self.frame.options.width,
                self.frame.options.height
            ),
        ];
        if let Some(which) = self.movables.get(self.moving) {
            lines.push(format!("ARROWS MOVE {}", which.describe(&self.scene)).to_uppercase());
        }
        if let Some(c) = self.technique.as_ref().and_then(|t| t.convergence()) {
            lines.push(format!("{} {:.1E}", c.measure, c.remaining).to_uppercase());
        }
        if let Some(status) = self.technique.as_ref().and_then(|t| t.status()) {
            lines.push(status.to_uppercase());
        }
        let passes = self.recent_pass_ms();
        lines.extend(
            passes
                .iter()
                .map(|(name, ms)| format!("{:<22}{ms:>8.2} MS", name.to_uppercase())),
        );
        if !self.status.is_empty() {
            lines.push(self.status.clone());
        }
        if self.help {
            lines.extend(help_lines(self.method_index().map(|i| &self.settings[i])));
        } else {
            lines.push("F1  KEYS".into());
        }
        lines
    }

    /// Per-pass GPU milliseconds per frame over the last collected frames, frame total first.
    fn recent_pass_ms(&mut self) -> Vec<(String, f64)> {
        let profiler = &mut self.ring.profiler;
        let samples = profiler.samples();
        let Some(last) = samples.iter().map(|s| s.frame).max() else {
            return Vec::new();
        };
        let first = last.saturating_sub(OVERLAY_FRAMES - 1);
        let frames = samples
            .iter()
            .filter(|s| s.frame >= first)
            .map(|s| s.frame)
            .collect::<HashSet<_>>()
            .len()
            .max(1) as f64;
        // A pass's runs in a frame (its parts, steps, layers and views) sum into one group.
        let mut totals: Vec<(&'static str, bool, f64)> = Vec::new();
        for sample in samples.iter().filter(|s| s.frame >= first) {
            let (pass, is_frame) = (sample.tag.pass, sample.tag.stage == Stage::Frame);
            match totals.iter_mut().find(|(name, _, _)| *name == pass) {
                Some(entry) => entry.2 += sample.duration_ns,
                None => totals.push((pass, is_frame, sample.duration_ns)),
            }
        }
        // The frame first, then the costliest passes.
        totals.sort_by(|a, b| (!a.1).cmp(&!b.1).then(b.2.total_cmp(&a.2)));
        let mut totals: Vec<(String, f64)> = totals
            .into_iter()
            .map(|(name, _, ns)| (name.to_string(), ns / (frames * 1e6)))
            .collect();
        totals.truncate(OVERLAY_PASSES + 1);
        if samples.len() > MAX_LIVE_SAMPLES && !self.recording_profile {
            profiler.clear();
        }
        totals
    }

    /// Save the first view (PNG, EXR) and the first window with its overlay (PNG).
    fn screenshot(&mut self, prefix: &Path) -> anyhow::Result<()> {
        self.ring.finish()?;
        self.gpu.wait_idle()?;
        let with = |suffix: &str| {
            let mut name = prefix.as_os_str().to_owned();
            name.push(suffix);
            PathBuf::from(name)
        };
        let view = self.frame.view();
        let size = (view.width(), view.height());
        output::write_images(
            Some(&with(".png")),
            Some(&with(".exr")),
            || Ok(self.frame.read_ldr(&self.gpu)?),
            || {
                Ok(HdrImage::new(
                    size.0,
                    size.1,
                    self.frame.read_hdr(&self.gpu)?,
                ))
            },
            size,
        )?;
        if let Some(cave) = &self.cave {
            for (index, wall) in cave.walls().iter().enumerate() {
                let (png, exr) = (
                    with(&format!("-{}.png", wall.name)),
                    with(&format!("-{}.exr", wall.name)),
                );
                output::write_view(&self.gpu, &self.frame, index, &png, &exr)?;
            }
        }
        let composed = &self.outputs[0].composed;
        let window_size = (composed.width(), composed.height());
        output::write_images(
            Some(&with("-window.png")),
            None,
            || Ok(self.gpu.read_image(composed)?),
            || anyhow::bail!("no EXR of the window is written"),
            window_size,
        )?;
        println!("saved {}.png, .exr and -window.png", prefix.display());
        Ok(())
    }

    /// Finish every frame, save what was asked, write the profile, check validation.
    fn shut_down(&mut self, args: &ViewArgs) -> anyhow::Result<()> {
        self.ring.finish()?;
        self.gpu.wait_idle()?;
        let technique = self.technique.as_deref();
        runner::add_notes(&self.gpu, &mut self.ring.profiler, &self.frame, technique);
        if let Some(prefix) = &args.screenshot {
            self.screenshot(prefix)?;
        }
        output::write_profile(&args.profile, &self.ring.profiler)
    }
}

/// The help: the viewer's keys, the method cycle, and the shown method's setting keys.
fn help_lines(settings: Option<&Settings>) -> Vec<String> {
    let mut lines: Vec<String> = HELP.iter().map(|l| l.to_string()).collect();
    lines.push(format!(
        "M  METHOD ({})",
        registry::method_names().join(", ").to_uppercase()
    ));
    let keys: Vec<String> = settings
        .map(|s| s.specs())
        .unwrap_or_default()
        .iter()
        .filter_map(|s| {
            let k = s.keys?;
            Some(format!(
                "{} {}  {} -/+",
                k.decrease,
                k.increase,
                s.name.to_uppercase()
            ))
        })
        .collect();
    if !keys.is_empty() {
        lines.push(keys.join("    "));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys the viewer uses itself (a method's setting keys must be others).
    const RESERVED_KEYS: &[char] = &['w', 'a', 's', 'd', 'q', 'e', 'm', 'i', 'o', 'p', 'l'];

    #[test]
    fn method_keys_are_free_and_map_to_keys() {
        for method in registry::methods() {
            let mut seen = Vec::new();
            for setting in method.settings {
                let Some(keys) = setting.keys else { continue };
                for c in [keys.decrease, keys.increase] {
                    assert!(
                        !RESERVED_KEYS.contains(&c),
                        "{}: '{c}' is the viewer's",
                        method.name
                    );
                    assert!(key_of(c).is_some(), "{}: '{c}' has no key", method.name);
                    assert!(!seen.contains(&c), "{}: '{c}' used twice", method.name);
                    seen.push(c);
                }
            }
        }
    }
}
