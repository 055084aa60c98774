//! Command-line arguments of every subcommand (clap). The binary parses these and hands them to
//! [`super::run`].

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use super::method_args::{MethodGrid, MethodSettings, method_parser};
use crate::gi::registry;
use crate::gpu::{GpuOptions, PixelPasses};
use crate::render::{FrameOptions, SubmitPlan};

/// The most frames `render`, `report` and `profile` run a configuration for (measured, and
/// warm-up apart): each measured frame keeps its passes' times until the run ends, and more
/// frames than this take hours without a steadier result.
const MAX_FRAMES: u32 = 100_000;

#[derive(Parser, Debug)]
#[command(
    name = "vkgi",
    version,
    about = "Real-time global illumination on Vulkan, measured against a reference path tracer"
)]
pub struct Cli {
    /// More log output (-v info, -vv debug).
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    pub verbose: u8,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene headless to PNG and/or OpenEXR, optionally profiling every pass.
    Render(RenderArgs),
    /// The windowed renderer: fly through a scene, move the light, switch methods (F1: keys);
    /// with --cave, the walls of a CAVE from one tracked head, sharing one GI light per frame.
    View(ViewArgs),
    /// Path-trace the ground-truth image of a scene (linear OpenEXR, settings beside it).
    Reference(ReferenceArgs),
    /// Error metrics (RMSE, relMSE, MAE, FLIP) of a linear HDR image against a reference.
    Compare(CompareArgs),
    /// Per-pass GPU time of every GI method per problem size (e.g. lattice), against the
    /// device's limits.
    Profile(ProfileCommandArgs),
    /// Every GI method over a grid of settings, scored against the cached reference: speed
    /// against error as report.md, report.json, plots and an image strip.
    Report(ReportArgs),
    /// The master of a CAVE run over several processes: owns the tracked head and the light,
    /// sends every render node versioned updates and holds them frame-locked.
    CaveMaster(CaveMasterArgs),
    /// One render node of a CAVE run: one wall, its own Vulkan device, the whole frame
    /// replicated, driven by `vkgi cave-master`.
    CaveNode(CaveNodeArgs),
    /// List the built-in scenes, or write one (or any scene vkgi reads: a glTF converted, say)
    /// as the files vkgi reads: OBJ, MTL, PNG textures and a scene file (.toml).
    Scene(SceneArgs),
}

/// Which GPU, and whether to validate.
#[derive(Args, Debug, Clone)]
pub struct GpuArgs {
    /// Device index or part of its name (default: VKGI_DEVICE, else discrete > integrated > CPU).
    #[arg(long)]
    pub device: Option<String>,
    /// Enable the Khronos validation layers (also VKGI_VALIDATE=1); errors fail the run.
    #[arg(long)]
    pub validate: bool,
    /// How direct lighting, the LPV lookup and tone mapping run: as fragment or compute passes
    /// (default: the faster on the device's type, as measured: fragment on a CPU device, compute
    /// on a GPU).
    #[arg(long, value_enum)]
    pub pixel_passes: Option<PixelPasses>,
}

impl GpuArgs {
    pub fn options(&self) -> GpuOptions {
        let from_env = std::env::var("VKGI_VALIDATE").is_ok_and(|v| v == "1" || v == "true");
        GpuOptions {
            validation: self.validate || from_env,
            device: self.device.clone(),
            display: None,
            pixel_passes: self.pixel_passes,
        }
    }
}

/// Image size, exposure and shadow-map resolution.
#[derive(Args, Debug, Clone)]
pub struct FrameArgs {
    /// Output size as WIDTHxHEIGHT.
    #[arg(long, default_value = "640x480", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Exposure in stops, applied before tone mapping (PNG only; the EXR stays linear).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Shadow-map resolution per light view.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1024)]
    pub shadow_map: u32,
    /// Render indirect light alone (no direct light, no emission), to score it against the
    /// reference's indirect part.
    #[arg(long)]
    pub indirect_only: bool,
    /// Cosine-lobed lights the rasteriser and the RSM-based methods sample the scene's emissive
    /// triangles with (the path tracer samples the triangles themselves).
    #[arg(long, default_value_t = crate::scene::DEFAULT_AREA_SAMPLES, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub area_samples: u32,
    /// How a GI method's independent parts (e.g. colour channels) are submitted: auto (async
    /// when the device has two or more compute queues), sequential (one command buffer), async
    /// (one submission per part, each on a compute queue).
    #[arg(long, visible_alias = "channels", value_enum, default_value_t = SubmitPlan::Auto)]
    pub parts: SubmitPlan,
    /// Treat the lights as moved in every frame: redo the shadow maps and the methods' RSMs and
    /// injection every frame, as a moving light costs (a frame whose lights and geometry did
    /// not change keeps them; `vkgi profile` and `vkgi report` always redo them).
    #[arg(long)]
    pub lights_move: bool,
    /// Draw the GI method's lookup as a pass of its own after direct lighting, where it is
    /// otherwise drawn inside direct lighting (LPV and ILPV), e.g. to time the two apart; the
    /// same image.
    #[arg(long)]
    pub lookup_apart: bool,
}

impl FrameArgs {
    pub fn options(&self) -> FrameOptions {
        FrameOptions {
            width: self.size.0,
            height: self.size.1,
            exposure_ev: self.exposure,
            shadow_map_size: self.shadow_map,
            indirect_only: self.indirect_only,
            submit: self.parts,
            lights_move: self.lights_move,
            lookup_apart: self.lookup_apart,
        }
    }
}

/// Where per-pass GPU times go.
#[derive(Args, Debug, Clone)]
pub struct ProfileArgs {
    /// Print per-pass GPU nanoseconds (avg/median/min/max/% of frame).
    #[arg(long)]
    pub profile: bool,
    /// Write the per-pass profile as JSON.
    #[arg(long, value_name = "FILE")]
    pub profile_json: Option<PathBuf>,
    /// Write a Chrome trace (chrome://tracing, Perfetto) of every timed pass.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
}

impl ProfileArgs {
    pub fn wanted(&self) -> bool {
        self.profile || self.profile_json.is_some() || self.trace.is_some()
    }
}

/// Which global-illumination method, and its settings (flags that come from the registry).
#[derive(Args, Debug, Clone)]
pub struct GiArgs {
    /// The global-illumination method.
    #[arg(
        long,
        visible_alias = "scheme",
        default_value = registry::default_name(),
        value_parser = method_parser(),
        ignore_case = true
    )]
    pub method: String,
    #[command(flatten)]
    pub settings: MethodSettings,
}

#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Built-in scene (see `vkgi scene --list`), a scene file (.toml), a glTF 2.0 scene (.gltf, .glb) or a mesh (.obj).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Tone-mapped PNG output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Linear radiance as 32-bit float OpenEXR.
    #[arg(long, value_name = "FILE")]
    pub hdr: Option<PathBuf>,
    /// Frames to render, 1 to 100000 (default: as many as the method needs to settle, e.g.
    /// until an incremental method's old light weighs less than 1%).
    #[arg(long, allow_negative_numbers = true, value_parser = frame_count(1))]
    pub frames: Option<u32>,
    #[command(flatten)]
    pub gi: GiArgs,
    #[command(flatten)]
    pub frame: FrameArgs,
    #[command(flatten)]
    pub profile: ProfileArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Built-in scene (see `vkgi scene --list`), a scene file (.toml), a glTF 2.0 scene (.gltf, .glb) or a mesh (.obj).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Present without waiting for vertical sync (mailbox or immediate when offered).
    #[arg(long)]
    pub no_vsync: bool,
    /// Show the front, left, right and floor walls of a CAVE around the camera, each an
    /// off-axis view from the tracked head, all lit by one shared GI light per frame.
    #[arg(long)]
    pub cave: bool,
    /// With --cave: one window per wall instead of the walls tiled in one window.
    #[arg(long, requires = "cave")]
    pub cave_windows: bool,
    /// With --cave: the tracked head relative to the CAVE's centre, in half wall sizes, as
    /// RIGHT,UP,BACK.
    #[arg(long, default_value = "0.2,0.1,0.3", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub head: glam::Vec3,
    /// With --cave: the CAVE's wall size as a fraction of the scene's diagonal.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.2)]
    pub cave_size: f32,
    /// With --cave: tracked samples that move the head (and the first light) frame by frame,
    /// as `vkgi cave-master --path` reads them (src/cave/path.rs).
    #[arg(long, value_name = "FILE", requires = "cave")]
    pub path: Option<PathBuf>,
    /// Close after this many frames (for scripts and tests).
    #[arg(long, allow_negative_numbers = true)]
    pub frames: Option<u64>,
    /// On closing, save the first view as PREFIX.png and PREFIX.exr, and the window with its
    /// overlay as PREFIX-window.png; with --cave also every wall as PREFIX-WALL.png and .exr.
    #[arg(long, value_name = "PREFIX")]
    pub screenshot: Option<PathBuf>,
    /// Ask the window for this size half-way through --frames (tests resizing).
    #[arg(long, value_parser = parse_size, requires = "frames")]
    pub resize_to: Option<(u32, u32)>,
    /// Press these keys, one per frame from the first, each held for that frame (scripts and
    /// tests), e.g. "m,],right,i,p". Names: a-z, 0-9, f1-f12, left, right, up, down, pageup,
    /// pagedown, [, ], comma, ., -, =, esc.
    #[arg(long, value_delimiter = ',', value_parser = parse_key)]
    pub keys: Vec<winit::keyboard::KeyCode>,
    #[command(flatten)]
    pub gi: GiArgs,
    #[command(flatten)]
    pub frame: FrameArgs,
    #[command(flatten)]
    pub profile: ProfileArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// Where a CAVE master listens unless told otherwise (loopback: a run on one machine).
pub const DEFAULT_CAVE_ADDRESS: &str = "127.0.0.1:7450";

/// What the master does when a node dies or stops answering.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnLoss {
    /// Say which wall was lost and go on with the others.
    Continue,
    /// Say which wall was lost, stop every other node cleanly and fail.
    Stop,
}

#[derive(Args, Debug, Clone)]
pub struct CaveMasterArgs {
    /// The scene every node renders (nodes of another scene are refused).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Address to listen on for nodes.
    #[arg(long, default_value = DEFAULT_CAVE_ADDRESS)]
    pub listen: String,
    /// How many nodes the run waits for before its first frame.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub nodes: u32,
    /// Frames to run.
    #[arg(long, default_value_t = 300, allow_negative_numbers = true)]
    pub frames: u64,
    /// Tracked samples, one line per frame: head RIGHT UP BACK in half-sizes, and optionally
    /// the first light's world position X Y Z (see src/cave/path.rs).
    #[arg(long, value_name = "FILE")]
    pub path: Option<PathBuf>,
    /// Without --path: the tracked head relative to the CAVE's centre, in half wall sizes.
    #[arg(long, default_value = "0.2,0.1,0.3", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub head: glam::Vec3,
    /// The CAVE's wall size as a fraction of the scene's diagonal.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.2)]
    pub cave_size: f32,
    /// The distance between a stereo node's eyes, as a fraction of the wall size (6.5 cm in
    /// a 3 m CAVE is 0.022).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.022)]
    pub eye_separation: f32,
    /// Nodes draw their walls half a pixel wider on every side, so the outer pixel centres lie
    /// on the edges and walls that meet both draw their shared edge (overlapping projectors).
    #[arg(long)]
    pub edge_pixels: bool,
    /// Seconds to wait for all nodes to join.
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    pub join_timeout: f64,
    /// Seconds a node may stay silent before it counts as lost.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub node_timeout: f64,
    /// What to do when a node is lost.
    #[arg(long, value_enum, default_value_t = OnLoss::Continue)]
    pub on_loss: OnLoss,
    /// Write the run's per-frame sync times and lattice digests as JSON.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Print a line per frame (sync latency and frame-lock wait).
    #[arg(long)]
    pub log_frames: bool,
    /// What every node draws with (exposure, shadow maps, indirect light only, area samples,
    /// parts); --size is the master's window.
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Open the master's window: its overlay (frame, version, sync times, walls) and the
    /// keyboard and mouse that move the head and the light.
    #[arg(long)]
    pub window: bool,
    /// Press these keys, one per frame from the first, each held for that frame (as `vkgi
    /// view --keys`; the master's keys: w a s d q e move the head, arrows and pageup/pagedown
    /// the light, esc stops).
    #[arg(long, value_delimiter = ',', value_parser = parse_key)]
    pub keys: Vec<winit::keyboard::KeyCode>,
    /// With --window: on stopping, save the master's window as PREFIX-window.png.
    #[arg(long, value_name = "PREFIX", requires = "window")]
    pub screenshot: Option<PathBuf>,
    #[command(flatten)]
    pub gi: GiArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
pub struct CaveNodeArgs {
    /// The scene (the master refuses a node whose scene differs from its own).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// The master's address.
    #[arg(long, default_value = DEFAULT_CAVE_ADDRESS)]
    pub master: String,
    /// The wall this node draws.
    #[arg(long, value_enum)]
    pub wall: crate::view::cave::WallName,
    /// Which eye it draws: mono (the head), left, right, or both from one frame pass.
    #[arg(long, value_enum, default_value_t = crate::view::cave::EyeChoice::Mono)]
    pub eye: crate::view::cave::EyeChoice,
    /// With --eye both: how the pair is shown without shutter glasses.
    #[arg(long, value_enum, default_value_t = crate::cave::stereo::StereoLayout::SideBySide)]
    pub stereo: crate::cave::stereo::StereoLayout,
    /// On stopping, save the wall as PREFIX-WALL.png and PREFIX-WALL.exr (one eye:
    /// PREFIX-WALL-EYE.*; both: each eye's, and the pair as --stereo lays it out in
    /// PREFIX-WALL-stereo.png; a windowed node also its window, overlay included, as
    /// PREFIX-WALL-window.png).
    #[arg(long, value_name = "PREFIX")]
    pub screenshot: Option<PathBuf>,
    /// Render without a window (save the wall with --screenshot).
    #[arg(long)]
    pub headless: bool,
    /// Seconds to keep trying to reach the master (a node may start first).
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    pub connect_timeout: f64,
    /// Seconds to wait for the master's next message before giving up on it.
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    pub master_timeout: f64,
    /// The node's window as WIDTHxHEIGHT; its views are the largest squares that fit (the
    /// master sets everything else the frame is drawn with).
    #[arg(long, default_value = "640x640", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
pub struct ReferenceArgs {
    /// Built-in scene (see `vkgi scene --list`), a scene file (.toml), a glTF 2.0 scene (.gltf, .glb) or a mesh (.obj).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Samples per pixel.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1024)]
    pub spp: u32,
    /// Indirect bounces: 0 = direct light only, 1 = direct + one bounce, 'inf' = unlimited.
    #[arg(long, default_value = "1", value_parser = crate::reference::Bounces::parse)]
    pub bounces: crate::reference::Bounces,
    /// Linear radiance as 32-bit float OpenEXR; the settings go to FILE.json beside it.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Also write a tone-mapped PNG.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// How emissive surfaces are sampled: mis (emitter sampling and BSDF hits combined by the
    /// power heuristic), light (emitter sampling alone) or bsdf (BSDF hits alone).
    #[arg(long, value_enum, default_value_t = crate::reference::Strategy::Mis)]
    pub strategy: crate::reference::Strategy,

    /// Where to trace: auto (the CPU's cores when the Vulkan device is a CPU, as lavapipe is; the
    /// device otherwise), gpu or cpu. The same estimator and random numbers either way; every
    /// choice opens a Vulkan device (its image limits apply to both).
    #[arg(long, value_enum, default_value_t = crate::reference::Tracer::Auto)]
    pub tracer: crate::reference::Tracer,
    /// Seed of the random numbers (the image is deterministic for a seed).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u32,
    /// Also write the direct and indirect parts (FILE stem + .direct.exr / .indirect.exr).
    #[arg(long)]
    pub split: bool,
    /// Skip rendering when FILE.json shows a split reference of the same scene, settings and code.
    #[arg(long)]
    pub reuse: bool,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "640x480", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Exposure in stops for the PNG.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Pose the scene's dynamic objects as frame K of their paths (`render --frames N` shows
    /// frame N-1).
    #[arg(
        long,
        value_name = "K",
        default_value_t = 0,
        allow_negative_numbers = true
    )]
    pub frame: u64,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
pub struct CompareArgs {
    /// The image to score (linear OpenEXR).
    pub test: PathBuf,
    /// The reference it is scored against (linear OpenEXR).
    pub reference: PathBuf,
    /// Count only the pixels that are white in this image (e.g. what a method models).
    #[arg(long, value_name = "PNG")]
    pub mask: Option<PathBuf>,
    /// Write the metrics as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write the FLIP error map as a heat map PNG.
    #[arg(long, value_name = "PNG")]
    pub heatmap: Option<PathBuf>,
    /// Accept 8- or 16-bit images (tone-mapped values taken as they are, not radiance).
    #[arg(long)]
    pub allow_ldr: bool,
}

#[derive(Args, Debug, Clone)]
pub struct ProfileCommandArgs {
    /// Built-in scene (see `vkgi scene --list`), a scene file (.toml), a glTF 2.0 scene (.gltf, .glb) or a mesh (.obj).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Methods to profile, comma-separated (default: every registered method).
    #[arg(long, value_delimiter = ',', value_parser = method_parser(), ignore_case = true)]
    pub method: Vec<String>,
    /// Measured frames per configuration, 1 to 100000.
    #[arg(long, allow_negative_numbers = true, default_value_t = 10, value_parser = frame_count(1))]
    pub frames: u32,
    /// Frames run before measuring, 0 to 100000.
    #[arg(long, allow_negative_numbers = true, default_value_t = 2, value_parser = frame_count(0))]
    pub warmup: u32,
    /// Image size as WIDTHxHEIGHT (the lookup and raster passes scale with it).
    #[arg(long, default_value = "320x240", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// How a method's independent parts are submitted (see `render --parts`).
    #[arg(long, visible_alias = "channels", value_enum, default_value_t = SubmitPlan::Auto)]
    pub parts: SubmitPlan,
    /// Time a method's lookup apart from direct lighting (see `render --lookup-apart`).
    #[arg(long)]
    pub lookup_apart: bool,
    /// Write the profile as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write one CSV line per pass.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Method settings: each method's size axis (e.g. --lattice 8,16,32) takes a list, which
    /// defaults to the values the report sweeps; any other setting takes one value.
    #[command(flatten)]
    pub grid: MethodGrid,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
pub struct ReportArgs {
    /// Built-in scene (see `vkgi scene --list`), a scene file (.toml), a glTF 2.0 scene (.gltf, .glb) or a mesh (.obj).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Folder for report.md, report.json, the plots, images/ and the cached reference.
    #[arg(long, value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "160x120", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Samples per pixel of the reference (bounces 1, reused when cached in DIR).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1024)]
    pub spp: u32,
    /// Methods, comma-separated (default: every registered method, the ambient baseline
    /// among them).
    #[arg(long, value_delimiter = ',', value_parser = method_parser(), ignore_case = true)]
    pub method: Vec<String>,
    /// Frames per run, 1 to 100000 (default: as many as each configuration needs to settle).
    #[arg(long, allow_negative_numbers = true, value_parser = frame_count(1))]
    pub frames: Option<u32>,
    /// Method settings as comma-separated lists: the grid is every combination (settings not
    /// given take the values the method sweeps by default, or its default).
    #[command(flatten)]
    pub grid: MethodGrid,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(Args, Debug, Clone)]
#[command(group(clap::ArgGroup::new("action").required(true).args(["list", "write"])))]
pub struct SceneArgs {
    /// The scene to write: a built-in name, a scene file (.toml), a glTF 2.0 scene (.gltf,
    /// .glb) or a mesh (.obj).
    #[arg(requires = "write")]
    pub scene: Option<String>,
    /// List the built-in scenes, a line about each.
    #[arg(long, conflicts_with = "scene")]
    pub list: bool,
    /// Folder to write SCENE into (created if missing): NAME.obj, NAME.mtl, NAME.toml and
    /// NAME-texture-K.png for each albedo texture; `vkgi render --scene DIR/NAME.toml` renders
    /// it as SCENE.
    #[arg(long, value_name = "DIR", requires = "scene")]
    pub write: Option<PathBuf>,
}

/// Parse `WIDTHxHEIGHT` (range checks happen against the device later).
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT"))?;
    let parse = |s: &str| {
        let s = s.trim();
        if s.starts_with('-') {
            return Err(format!("'{text}': sizes are whole numbers of at least 1"));
        }
        s.parse::<u32>()
            .map_err(|_| format!("'{text}' is not WIDTHxHEIGHT with whole numbers"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// Parse a key name of `--keys`.
pub fn parse_key(text: &str) -> Result<winit::keyboard::KeyCode, String> {
    use winit::keyboard::KeyCode as K;
    let name = text.trim().to_ascii_lowercase();
    let letters = [
        K::KeyA,
        K::KeyB,
        K::KeyC,
        K::KeyD,
        K::KeyE,
        K::KeyF,
        K::KeyG,
        K::KeyH,
        K::KeyI,
        K::KeyJ,
        K::KeyK,
        K::KeyL,
        K::KeyM,
        K::KeyN,
        K::KeyO,
        K::KeyP,
        K::KeyQ,
        K::KeyR,
        K::KeyS,
        K::KeyT,
        K::KeyU,
        K::KeyV,
        K::KeyW,
        K::KeyX,
        K::KeyY,
        K::KeyZ,
    ];
    let digits = [
        K::Digit0,
        K::Digit1,
        K::Digit2,
        K::Digit3,
        K::Digit4,
        K::Digit5,
        K::Digit6,
        K::Digit7,
        K::Digit8,
        K::Digit9,
    ];
    let functions = [
        K::F1,
        K::F2,
        K::F3,
        K::F4,
        K::F5,
        K::F6,
        K::F7,
        K::F8,
        K::F9,
        K::F10,
        K::F11,
        K::F12,
    ];
    let single = name.chars().next().filter(|_| name.chars().count() == 1);
    let code = match (name.as_str(), single) {
        (_, Some(c @ 'a'..='z')) => letters[(c as u8 - b'a') as usize],
        (_, Some(c @ '0'..='9')) => digits[(c as u8 - b'0') as usize],
        ("[", _) => K::BracketLeft,
        ("]", _) => K::BracketRight,
        (".", _) => K::Period,
        ("-", _) => K::Minus,
        ("=", _) => K::Equal,
        (";", _) => K::Semicolon,
        ("'", _) => K::Quote,
        ("/", _) => K::Slash,
        ("left", _) => K::ArrowLeft,
        ("right", _) => K::ArrowRight,
        ("up", _) => K::ArrowUp,
        ("down", _) => K::ArrowDown,
        ("pageup", _) => K::PageUp,
        ("pagedown", _) => K::PageDown,
        ("esc", _) => K::Escape,
        ("comma", _) => K::Comma,
        (f, _) if f.starts_with('f') => match f[1..].parse::<usize>() {
            Ok(n @ 1..=12) => functions[n - 1],
            _ => return Err(format!("unknown key '{text}'")),
        },
        _ => return Err(format!("unknown key '{text}'")),
    };
    Ok(code)
}

/// Parse "X,Y,Z" into a vector of finite numbers.
pub fn parse_vec3(text: &str) -> Result<glam::Vec3, String> {
    let parts: Vec<f32> = text
        .split(',')
        .map(|s| s.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}' is not X,Y,Z"))?;
    match parts[..] {
        [x, y, z] if parts.iter().all(|v| v.is_finite()) => Ok(glam::Vec3::new(x, y, z)),
        _ => Err(format!("'{text}' is not X,Y,Z with three finite numbers")),
    }
}

/// A frame count from `least` to [`MAX_FRAMES`].
fn frame_count(least: i64) -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(least..=i64::from(MAX_FRAMES))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert_eq!(parse_size("0x0"), Ok((0, 0)));
        assert!(parse_size("640").is_err());
        assert!(parse_size("-1x5").is_err());
        assert!(parse_size("axb").is_err());
    }

    #[test]
    fn cli_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
