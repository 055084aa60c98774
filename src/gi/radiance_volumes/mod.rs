//! `radiance-volumes`, seed 001 (Reich, "Realtime Global Illumination using Dynamic Radiance
//! Volumes", 2015; spec 001, rebuilt from the author's public code): camera-centred cascaded
//! grids of light caches, rebuilt every frame. Each view's lit pixels allocate the caches at the
//! corners of their cells (and nowhere else); every cache is lit by every virtual area light
//! (blocks of the RSM) and keeps its light as 2 or 3 SH bands; each pixel interpolates the
//! irradiance of its 8 corner caches. Nothing is kept between frames, so lights, camera and
//! geometry are followed in the frame they move.

pub mod bindings;
pub mod cascades;
pub mod cost;
pub mod cpu;
pub mod passes;
pub mod specular;
pub mod voxelizer;
pub mod voxels;

use crate::error::InputError;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};
use crate::gi::{FrameContext, GiMethod, PixelPass};
use crate::gpu::{Gpu, GpuResult, Recorder};
use crate::scene::Scene;
use crate::scene::dynamic::Aabb;
use passes::{Passes, RvState};

const SETTINGS: &[Setting] = &[
    Setting::new(
        "cascades",
        Kind::Int {
            min: 1,
            max: cascades::MAX_CASCADES as i64,
        },
        "3",
        "Cascades of cache grids around the camera, each twice as wide as the one before",
    ),
    Setting::new(
        "resolution",
        Kind::Int { min: 4, max: 256 },
        "32",
        "Cells per side of every cascade (caches sit at the cells' corners)",
    )
    .keys('9', '0', 2.0),
    Setting::new(
        "reach",
        Kind::Float {
            min: 0.01,
            max: 100.0,
        },
        "1",
        "How far the last cascade reaches from the camera, as a fraction of the scene's farthest point from its camera (1: all of it; the public code: fixed cascades of 4, 8 and 16 m)",
    ),
    Setting::new(
        "transition",
        Kind::Float { min: 0.0, max: 10.0 },
        "2",
        "Cells near a cascade's edge over which it blends into the next (0: a hard seam)",
    ),
    Setting::new(
        "caches",
        Kind::Int { min: 1, max: 1 << 20 },
        "16384",
        "Caches a frame may hold; corners past it are refused and counted, and pixels weight the corners they have",
    ),
    Setting::new(
        "sh",
        Kind::Choice(&["l1", "l2"]),
        "l1",
        "SH bands a cache keeps its light in: l1 (4 coefficients, the public code's default) or l2 (9)",
    ),
    Setting::new(
        "rsm",
        Kind::Choice(&["64", "128", "256", "512", "1024", "2048"]),
        "256",
        "Reflective-shadow-map resolution per light view",
    ),
    Setting::new(
        "vals",
        Kind::Int {
            min: 1,
            max: 1 << 20,
        },
        "4096",
        "Virtual area lights a frame may light the caches with: the RSM is read at the finest mip level whose texels over all light views number at most this (the public code: 64² of one spot light)",
    ),
    Setting::new(
        "corners",
        Kind::Choice(&["all", "front"]),
        "all",
        "Which of a pixel's 8 corner caches it interpolates: all (the public code), or those in front of its surface (corners behind it may sit inside the object or beyond a wall)",
    ),
    Setting::new(
        "indirect-shadows",
        Kind::Choice(&["on", "off"]),
        "on",
        "Cone-trace each block of VALs' visibility through a voxelisation of the scene (off: every VAL reaches every cache)",
    ),
    Setting::new(
        "voxels",
        Kind::Choice(&["32", "64", "128", "256"]),
        "128",
        "Voxels per side of the cube around the scene the shadow cones march through",
    ),
    Setting::new(
        "voxelizer",
        Kind::Choice(&["auto", "compute", "raster"]),
        "auto",
        "How the scene is voxelised: compute (every device), raster (conservative rasterisation, the public code's path; without VK_EXT_conservative_rasterization it misses thin slivers, for tests) or auto (raster where the device rasterises conservatively)",
    ),
    Setting::new(
        "shadow-lod",
        Kind::Int { min: 0, max: 8 },
        "2",
        "One shadow cone per 2^L x 2^L block of VALs, aimed at the block's mean VAL",
    ),
    Setting::new(
        "specular",
        Kind::Choice(&["auto", "off", "4", "8", "16", "32"]),
        "auto",
        "Side of each cache's hemisphere map of incoming light, which glossy surfaces reflect (spec 001 §4.7): 4 to 32 texels, off, or auto (8 where a material is glossier than a rough 4% dielectric, else off)",
    ),
    Setting::new(
        "voxel-fade",
        Kind::Int { min: 1, max: 120 },
        "3",
        "Frames over which a voxel fades between empty and full after geometry moves (the public code: 0.1 s; 1: at once)",
    ),
];

pub const METHODS: &[MethodEntry] = &[MethodEntry {
    name: "radiance-volumes",
    description: "seed 001: dynamic radiance volumes, cascaded grids of SH light caches allocated every frame where the view needs them and lit by the RSM's virtual area lights",
    default: false,
    settings: SETTINGS,
    // Every frame is complete but for voxels fading in over voxel-fade frames after geometry
    // moved (a moved object is followed once they have); at least two frames, so the profile
    // reports the first frame's counters, which the host reads a frame late.
    settle_frames: |settings| settings.u32("voxel-fade").unwrap_or(1).max(1) + 1,
    profile_axis: None,
    create: |setup, settings| Ok(Box::new(RadianceVolumes::new(setup, settings)?)),
}];

/// SH bands a cache keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bands {
    L1,
    L2,
}

impl Bands {
    pub fn coefficients(self) -> u32 {
        match self {
            Bands::L1 => 4,
            Bands::L2 => 9,
        }
    }
}

/// The method's settings, parsed and checked.
#[derive(Clone, Debug)]
pub struct VolumeSettings {
    pub cascades: u32,
    pub resolution: u32,
    /// How far the last cascade reaches, as a fraction of the scene's farthest point from its
    /// camera.
    pub reach: f32,
    pub transition: f32,
    pub capacity: u32,
    pub bands: Bands,
    pub rsm: u32,
    pub val_budget: u32,
    /// Interpolate only the corners in front of the pixel's surface.
    pub front_corners: bool,
    pub shadows: bool,
    pub voxels: u32,
    pub voxelizer: voxelizer::VoxelizerChoice,
    pub shadow_lod: u32,
    pub voxel_fade: u32,
    /// Side of each cache's specular hemisphere map (0: no indirect specular).
    pub specular: u32,
}

/// The map side `--specular auto` picks for a scene with a glossy material.
pub const AUTO_SPECULAR_SIDE: u32 = 8;

impl VolumeSettings {
    /// The settings for `scene` (which decides `--specular auto`).
    pub fn parse(settings: &Settings, scene: &Scene) -> Result<Self, InputError> {
        let rsm = settings.text("rsm")?;
        // Choices of whole numbers (powers of two), already checked against their lists.
        let parse_whole = |name: &str, text: &str| {
            text.parse::<u32>()
                .map_err(|_| InputError::new(format!("--{name} {text}: not a whole number")))
        };
        Ok(VolumeSettings {
            cascades: settings.u32("cascades")?,
            resolution: settings.u32("resolution")?,
            reach: settings.float("reach")? as f32,
            transition: settings.float("transition")? as f32,
            capacity: settings.u32("caches")?,
            bands: if settings.text("sh")? == "l2" {
                Bands::L2
            } else {
                Bands::L1
            },
            rsm: parse_whole("rsm", rsm)?,
            val_budget: settings.u32("vals")?,
            front_corners: settings.text("corners")? == "front",
            shadows: settings.text("indirect-shadows")? == "on",
            voxels: parse_whole("voxels", settings.text("voxels")?)?,
            voxelizer: voxelizer::VoxelizerChoice::parse(settings.text("voxelizer")?)?,
            shadow_lod: settings.u32("shadow-lod")?,
            voxel_fade: settings.u32("voxel-fade")?,
            specular: match settings.text("specular")? {
                "off" => 0,
                "auto" if scene.materials.iter().any(|m| m.is_visibly_glossy()) => {
                    AUTO_SPECULAR_SIDE
                }
                "auto" => 0,
                side => parse_whole("specular", side)?,
            },
        })
    }
}

pub struct RadianceVolumes {
    pub settings: VolumeSettings,
    pub passes: Passes,
}

impl RadianceVolumes {
    pub fn new(setup: &Setup, settings: &Settings) -> anyhow::Result<RadianceVolumes> {
        RadianceVolumes::with(setup, VolumeSettings::parse(settings, setup.scene)?)
    }

    pub fn with(setup: &Setup, settings: VolumeSettings) -> anyhow::Result<RadianceVolumes> {
        let passes = Passes::new(setup.gpu, setup.scene, &settings)?;
        Ok(RadianceVolumes { settings, passes })
    }

    /// The counters of the frame before the most recent finished one (the host copies them a
    /// frame late, so every view records the same passes).
    pub fn state(&self) -> RvState {
        self.passes.last_state()
    }
}

impl GiMethod for RadianceVolumes {
    fn name(&self) -> &'static str {
        "radiance-volumes"
    }

    fn record_view(&mut self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        if view == 0 {
            // Every view of a frame shares the cascades: around the first view's eye (a CAVE's
            // walls all have the tracked head's).
            self.passes.place(ctx.views[0].eye.position, &self.settings);
        }
        self.passes
            .record_allocate(rec, &ctx.views[view], &self.settings)
    }

    fn record_light(&mut self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        self.passes.record_light(rec, ctx, &self.settings)
    }

    fn record_lookup(&self, rec: &mut Recorder, ctx: &FrameContext, view: usize) -> GpuResult<()> {
        self.passes
            .record_apply(rec, &ctx.views[view], &self.settings)
    }

    fn pixel_passes(&self) -> Vec<PixelPass> {
        cost::apply_pass(&self.settings).into_iter().collect()
    }

    fn geometry_moved(
        &mut self,
        _gpu: &Gpu,
        _scene: &Scene,
        regions: &[Aabb],
    ) -> anyhow::Result<crate::gi::Follow> {
        // The RSM and the G-buffer are drawn from the frame's vertex buffer every frame and the
        // voxels are redrawn from it in the next frame; only the voxel cube, fitted to the
        // scene when the method was built, cannot follow geometry that leaves it.
        let g = &self.passes.voxels.grid;
        let hi = g.min + glam::Vec3::splat(g.voxel * g.resolution as f32);
        let inside = regions
            .iter()
            .all(|r| r.min.cmpge(g.min).all() && r.max.cmple(hi).all());
        Ok(if inside || !self.settings.shadows {
            crate::gi::Follow::Followed
        } else {
            crate::gi::Follow::Rebuild
        })
    }

    fn describe(&self) -> Vec<String> {
        let s = &self.settings;
        let p = &self.passes;
        let state = self.state();
        let memory = p.memory();
        let total: u64 = memory.iter().map(|(_, b)| b).sum();
        vec![
            format!(
                "radiance volumes: {} cascades of {}³ cells, the first {:.4} wide (cells {:.4} to {:.4}), transition {} cells, {:?}, at most {} caches",
                s.cascades,
                s.resolution,
                p.first_side,
                p.first_side / s.resolution as f32,
                p.first_side * (1u32 << (s.cascades - 1)) as f32 / s.resolution as f32,
                s.transition,
                s.bands,
                s.capacity
            ),
            format!(
                "radiance volumes: RSM {}² x {} views read as {} VALs ({}² texels each), chain of {} levels",
                p.rsm.size,
                p.rsm.layers,
                p.val_count(),
                p.block,
                p.levels.len()
            ),
            if s.shadows {
                let g = &p.voxels.grid;
                let (level, chain) = p.shadow_level(s);
                format!(
                    "radiance volumes: indirect shadows through {}³ voxels of {:.4} ({} levels, voxelised by {}), one cone per {}x{} VALs ({} cones per cache), voxels fade over {} frame(s)",
                    g.resolution,
                    g.voxel,
                    g.levels(),
                    match &p.voxels.raster {
                        None => "compute",
                        Some(r) if r.conservative => "conservative rasterisation",
                        Some(_) => "rasterisation without the conservative extension",
                    },
                    1u32 << level,
                    1u32 << level,
                    chain.side.pow(2) * p.rsm.layers,
                    s.voxel_fade
                )
            } else {
                "radiance volumes: no indirect shadows (every VAL reaches every cache)".into()
            },
            if s.specular > 0 {
                format!(
                    "radiance volumes: indirect specular from a {}² hemisphere map per cache",
                    s.specular,
                )
            } else {
                "radiance volumes: no indirect specular".into()
            },
            format!(
                "radiance volumes: {} caches held in the frame before the last, {} refused (cache buffer full), {} corners missing, {} pixels beyond the cascades",
                state.held(s.capacity),
                state.refused,
                state.missing,
                state.beyond
            ),
            format!(
                "radiance volumes: memory {:.2} MiB ({})",
                total as f64 / (1u64 << 20) as f64,
                memory
                    .iter()
                    .map(|(what, bytes)| format!("{what} {:.1} KiB", *bytes as f64 / 1024.0))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ]
    }

    fn status(&self) -> Option<String> {
        let state = self.state();
        Some(format!(
            "caches {}{}{}",
            state.held(self.settings.capacity),
            if state.refused > 0 {
                format!(", {} refused: buffer full", state.refused)
            } else {
                String::new()
            },
            if state.beyond > 0 {
                format!(", {} pixels beyond the cascades", state.beyond)
            } else {
                String::new()
            }
        ))
    }
}
