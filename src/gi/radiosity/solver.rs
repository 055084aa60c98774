//! Radiosity on the GPU (spec 004): the element buffers, the item buffer, and the passes of one
//! shot, recorded without a read-back: the selection pass writes the shooter into a buffer that
//! every later pass of the shot reads, so a frame can record many shots and converged shots
//! cost only empty passes. Progressive refinement (§4) shoots the most unshot power first; the
//! importance-driven mode (§5) also shoots importance from the user's camera and weights the
//! choice by it; the perspective-driven mode (§6) also keeps the share of receivers out of the
//! simulated view in a stored table ([`StoredTable`]) until they come into view.

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use super::bindings as ids;
use super::camera::CameraView;
use super::elements::{Elements, NO_SURFACE};
use super::table::StoredTable;
use crate::gpu::dispatch::{MAX_WORKGROUPS_X, rows_of_workgroups};
use crate::gpu::{
    Depth,
    Binding, Draw, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Image, ImageDesc,
    RasterPass, RasterPipeline, RasterPipelineDesc, Recorder, Specialization,
};
use crate::scene::{Light, LightKind, Scene};
use crate::shader_shared::LINEAR_WORKGROUP;
use crate::shaders;

/// Which surfaces shoot first, and which receive (spec 004 §4–6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Progressive refinement: the most unshot power first.
    Pr,
    /// Importance-driven: the most importance-weighted unshot power first.
    Id,
    /// Perspective-driven: as `Id`, and only surfaces in the simulated view receive.
    Pd,
}

impl Mode {
    pub const NAMES: &'static [&'static str] = &["pr", "id", "pd"];

    pub fn parse(name: &str) -> Option<Mode> {
        match name {
            "pr" => Some(Mode::Pr),
            "id" => Some(Mode::Id),
            "pd" => Some(Mode::Pd),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        Mode::NAMES[self as usize]
    }

    /// Whether the user's camera steers it.
    pub fn follows_camera(self) -> bool {
        self != Mode::Pr
    }
}

/// How the solver runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverOptions {
    pub mode: Mode,
    /// Five perspective faces instead of the thesis's one stereographic pass.
    pub hemicube: bool,
    /// Side of the item buffer (each hemicube face).
    pub resolution: u32,
    /// 1-to-4 subdivisions of the item-buffer mesh.
    pub item_level: u32,
    /// Most shooting locations per shot (each surface shoots from blocks of its texels, as few
    /// levels up as keep it within this).
    pub locations: u32,
    /// Converged once the most unshot power of any surface is below this fraction of the most
    /// unshot power there was.
    pub epsilon: f32,
}

crate::push_constants! {
    struct StatsPush {
        surface_count: u32,
    }
}

crate::push_constants! {
    struct SelectPush {
        reflectance_sum: [f32; 4],
        surface_count: u32,
        total_area: f32,
        epsilon: f32,
        mode: u32,
    }
}

crate::push_constants! {
    struct ItemPush {
        camera: [[f32; 4]; 4],
        eye: [f32; 4],
        slot: u32,
        face: u32,
        projection: u32,
        far: f32,
    }
}

crate::push_constants! {
    struct QuantityPush {
        quantity: u32,
    }
}

crate::push_constants! {
    struct GatherPush {
        slot: u32,
        element_count: u32,
        hemicube: u32,
        resolution: u32,
        bias: f32,
        quantity: u32,
        flags: u32,
        surface_count: u32,
    }
}

crate::push_constants! {
    struct ViewPush {
        camera: [[f32; 4]; 4],
        eye: [f32; 4],
        forward: [f32; 4],
        element_count: u32,
        resolution: u32,
        bias: f32,
        scale: f32,
        flags: u32,
    }
}

/// `SELECT_*` in select.comp.
const SELECT_POWER: u32 = 0;
const SELECT_IMPORTANCE_WEIGHTED: u32 = 1;
const SELECT_IMPORTANCE_SHOOTER: u32 = 2;
/// `ITEM_*` in item_buffer.vert.
const ITEM_STEREOGRAPHIC: u32 = 0;
const ITEM_HEMICUBE: u32 = 1;
const ITEM_CAMERA: u32 = 2;
/// `QUANTITY_*` and `GATHER_*` in radiosity.glsl.
const QUANTITY_RADIOSITY: u32 = 0;
const QUANTITY_IMPORTANCE: u32 = 1;
const GATHER_RESTRICT: u32 = 1;
const GATHER_DELIVER: u32 = 2;
/// `VIEW_*` in view.comp.
const VIEW_IMPORTANCE: u32 = 1;
const VIEW_VISIBILITY: u32 = 2;

/// An element's distance may exceed the nearest surface's in its item-buffer texel by this
/// fraction and still count as seen (the texel's footprint on slanted receivers).
const VISIBILITY_BIAS: f32 = 0.02;

/// The solver's state as the GPU last left it (see `Shot` in radiosity.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShotState {
    pub shooter: u32,
    pub level: u32,
    pub blocks: [u32; 2],
    /// The ambient irradiance still to arrive.
    pub ambient: [f32; 4],
    /// Unshot power now, the most there was, the last shooter's, shots done.
    pub power: [f32; 4],
    /// pd: table columns waiting for a delivery as of the last pick, and the view generation
    /// that pick saw.
    pub table: [u32; 4],
}

impl ShotState {
    pub fn converged(&self) -> bool {
        self.shooter == NO_SURFACE
    }

    pub fn shots(&self) -> u32 {
        self.power[3] as u32
    }

    /// Whether the table may still hold deliveries for the simulated view of `generation`
    /// (pd): unless a pick in that view found none.
    pub fn may_deliver(&self, generation: u32) -> bool {
        self.table[1] != generation || self.table[0] > 0
    }

    /// Unshot power as a fraction of the most there was.
    pub fn remaining(&self) -> f64 {
        if self.power[1] > 0.0 {
            f64::from(self.power[0] / self.power[1])
        } else {
            0.0
        }
    }
}

/// GPU surface layout (`SurfaceRecord` in radiosity.glsl; the display and the gather read it
/// as six RGBA32UI texels).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuSurface {
    origin_texel: [f32; 4],
    axis_t_area: [f32; 4],
    axis_b: [f32; 4],
    normal: [f32; 4],
    emission: [f32; 4],
    grid: [u32; 4],
}

/// GPU shooting location (`Location` in radiosity.glsl).
#[repr(C)]
#[derive(Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuLocation {
    position_area: [f32; 4],
    normal_kind: [f32; 4],
    emitted: [f32; 4],
    reflected: [f32; 4],
}

const LOCATION_LIGHT: f32 = 2.0;

pub struct Solver {
    pub elements: Elements,
    options: SolverOptions,
    slots: u32,
    surfaces: Buffer,
    element_data: Buffer,
    unshot: Buffer,
    direct: Buffer,
    indirect: Buffer,
    stats: Buffer,
    emission_unshot: Buffer,
    shot: Buffer,
    /// Per element: total, unshot and directly received importance (id, pd).
    importance: Buffer,
    importance_unshot: Buffer,
    importance_received: Buffer,
    importance_stats: Buffer,
    importance_shot: Buffer,
    /// Per surface: 1 when in the (simulated) view (pd).
    visible: Buffer,
    table: StoredTable,
    /// The shot state copied where the CPU can read it without waiting.
    shot_copy: Buffer,
    locations: Buffer,
    item_vertices: Buffer,
    item_triangles: Buffer,
    item_vertex_count: u32,
    item_ids: Image,
    item_distance: Image,
    item_depth: Image,
    stats_pass: ComputePipeline,
    /// Workgroups of the stats pass: one subgroup a surface, at most [`MAX_WORKGROUPS_X`]
    /// (its subgroups stride over the rest).
    stats_groups: u32,
    select_pass: ComputePipeline,
    locations_pass: ComputePipeline,
    gather_pass: ComputePipeline,
    finish_pass: ComputePipeline,
    view_pass: ComputePipeline,
    item_pass: RasterPipeline,
    reflectance_sum: Vec3,
    total_area: f32,
    far: f32,
    /// Importance of an element at unit distance on the camera's axis (the thesis's
    /// importanceEnergyConstant, its value not given): the scene's squared diagonal, so an
    /// element seen across the scene gets importance of order 1.
    importance_scale: f32,
}

impl Solver {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        elements: Elements,
        options: SolverOptions,
    ) -> anyhow::Result<Solver> {
        gpu.info.require_compute_subgroup_arithmetic(
            "radiosity",
            "its stats pass sums each surface in a subgroup",
        )?;
        let slots = options.locations.max(1);
        let element_count = elements.elements.len().max(1);
        let vec4_bytes = element_count as u64 * 16;
        // The display reads the elements, their indirect irradiance and the surfaces as texels.
        crate::render::targets::check_texel_buffer(
            gpu,
            &format!("radiosity's {element_count} elements"),
            vec4_bytes * 2,
        )?;
        let surface_data: Vec<GpuSurface> = elements
            .surfaces
            .iter()
            .map(|s| {
                let patch = &elements.patches[s.patch as usize];
                let mut level = 0;
                while s.width.div_ceil(1 << level) * s.height.div_ceil(1 << level) > slots {
                    level += 1;
                }
                GpuSurface {
                    origin_texel: patch.origin.extend(elements.texel).to_array(),
                    axis_t_area: patch.axis_t.extend(s.area as f32).to_array(),
                    axis_b: patch.axis_b.extend(0.0).to_array(),
                    normal: s.normal.extend(0.0).to_array(),
                    emission: s.emission.extend(0.0).to_array(),
                    grid: [s.first, s.width, s.height, level],
                }
            })
            .collect();
        let texels = vk::Format::R32G32B32A32_UINT;
        let surface_count = surface_data.len().max(1);
        crate::render::targets::check_texel_buffer(
            gpu,
            &format!("radiosity's {surface_count} surfaces"),
            (surface_count * std::mem::size_of::<GpuSurface>()) as u64,
        )?;
        let surfaces = gpu.upload_texel_items("radiosity surfaces", surface_count, texels, |i| {
            surface_data.get(i).copied().unwrap_or(bytemuck::Zeroable::zeroed())
        })?;
        let element_data =
            gpu.upload_texel_items("radiosity elements", element_count, texels, |i| {
                let e = elements.elements.get(i).copied().unwrap_or_default();
                [
                    e.position.extend(e.area).to_array(),
                    e.albedo.extend(f32::from_bits(e.surface)).to_array(),
                ]
            })?;
        let (item_vertices, item_triangles) = item_mesh(scene, &elements, options.item_level);
        let item_vertex_count = item_vertices.len() as u32;
        let layers = if options.hemicube { 5 } else { 1 };
        let layered = |name, format, usage| {
            let mut desc = ImageDesc::new_2d(name, format, options.resolution, options.resolution, usage);
            desc.layers = layers;
            desc.array = true;
            gpu.create_image(&desc)
        };
        let storage = |name: &str, bytes: u64| gpu.create_buffer(&BufferDesc::storage(name, bytes.max(16)));
        let (lo, hi) = scene.mesh.bounds();
        let compute = |name, spirv| ComputePipeline::new(gpu, name, spirv, &Specialization::new());
        let surface_count = elements.surfaces.len() as u64;
        let albedo = elements.mean_albedo().min(Vec3::splat(0.999));
        let scalar_bytes = element_count as u64 * 4;
        let table = StoredTable::new(gpu, surface_count as u32, slots, options.mode == Mode::Pd)?;
        Ok(Solver {
            options,
            slots,
            surfaces,
            element_data,
            unshot: storage("radiosity unshot", vec4_bytes)?,
            direct: storage("radiosity direct irradiance", vec4_bytes)?,
            indirect: gpu.create_buffer(&BufferDesc::storage_uint_texels(
                "radiosity indirect irradiance",
                vec4_bytes,
            ))?,
            stats: storage("radiosity surface stats", surface_count * 16)?,
            emission_unshot: storage("radiosity emission unshot", surface_count * 4)?,
            shot: storage("radiosity shot", std::mem::size_of::<ShotState>() as u64)?,
            importance: storage("radiosity importance", scalar_bytes)?,
            importance_unshot: storage("radiosity unshot importance", scalar_bytes)?,
            importance_received: storage("radiosity received importance", scalar_bytes)?,
            importance_stats: storage("radiosity importance stats", surface_count * 16)?,
            importance_shot: storage("radiosity importance shot", std::mem::size_of::<ShotState>() as u64)?,
            visible: storage("radiosity surfaces in view", surface_count * 4)?,
            table,
            shot_copy: gpu.create_buffer(&BufferDesc {
                name: "radiosity shot (host copy)",
                size: std::mem::size_of::<ShotState>() as u64,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
                texels: None,
            })?,
            locations: storage(
                "radiosity locations",
                u64::from(slots.max(2)) * std::mem::size_of::<GpuLocation>() as u64,
            )?,
            item_vertices: gpu.upload_texel_items(
                "radiosity item-buffer mesh",
                item_vertices.len().max(3),
                vk::Format::R32G32B32A32_SFLOAT,
                |i| item_vertices.get(i).copied().unwrap_or_default(),
            )?,
            item_triangles: gpu.upload_texel_items(
                "radiosity item-buffer sides",
                item_triangles.len(),
                vk::Format::R32G32B32A32_UINT,
                |i| item_triangles.get(i).copied().unwrap_or_default(),
            )?,
            item_vertex_count,
            item_ids: layered(
                "radiosity item ids",
                vk::Format::R32_UINT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
            )?,
            item_distance: layered(
                "radiosity item distance",
                vk::Format::R32_SFLOAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
            )?,
            item_depth: layered(
                "radiosity item depth",
                vk::Format::D32_SFLOAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            )?,
            stats_pass: compute("radiosity stats", shaders::GI_RADIOSITY_STATS_COMP)?,
            stats_groups: stats_workgroups(surface_count as u32, gpu.info.subgroup_size),
            select_pass: compute("radiosity select", shaders::GI_RADIOSITY_SELECT_COMP)?,
            locations_pass: compute("radiosity locations", shaders::GI_RADIOSITY_LOCATIONS_COMP)?,
            gather_pass: compute("radiosity gather", shaders::GI_RADIOSITY_GATHER_COMP)?,
            finish_pass: compute("radiosity finish", shaders::GI_RADIOSITY_FINISH_COMP)?,
            view_pass: compute("radiosity view", shaders::GI_RADIOSITY_VIEW_COMP)?,
            item_pass: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: "radiosity item buffer",
                    vertex: shaders::GI_RADIOSITY_ITEM_BUFFER_VERT,
                    fragment: Some(shaders::GI_RADIOSITY_ITEM_BUFFER_FRAG),
                    color_formats: &[vk::Format::R32_UINT, vk::Format::R32_SFLOAT],
                    depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                    depth_bias: None,
                    additive_blend: false,
                    conservative: false,
                    specialization: &Specialization::new(),
                },
            )?,
            reflectance_sum: Vec3::ONE / (Vec3::ONE - albedo),
            total_area: elements.surfaces.iter().map(|s| s.area).sum::<f64>() as f32,
            far: 4.0 * (hi - lo).length().max(1e-6),
            importance_scale: (hi - lo).length_squared().max(1e-12),
            elements,
        })
    }

    /// Shooting-location slots one shot records.
    pub fn slots(&self) -> u32 {
        self.slots
    }

    pub fn options(&self) -> SolverOptions {
        self.options
    }

    /// Forget the solution and start again: clear every element, mark every emitter unshot,
    /// forget the importance and the stored table, and shoot the punctual lights (each first,
    /// as point emitters, to every receiver: the modes steer only the surfaces' shots).
    pub fn record_restart(&self, rec: &mut Recorder, lights: &[Light]) -> GpuResult<()> {
        let mut fills = vec![
            (&self.unshot, 0),
            (&self.direct, 0),
            (&self.indirect, 0),
            (&self.shot, 0),
            (&self.importance, 0),
            (&self.importance_unshot, 0),
            (&self.importance_received, 0),
            (&self.importance_shot, 0),
            (&self.visible, 0),
            (&self.emission_unshot, 1),
        ];
        fills.extend(self.table.clearing_fills());
        rec.fill_buffers("radiosity clear", &fills);
        for light in lights {
            let locations = light_locations(light);
            rec.update_buffer("radiosity light locations", &self.locations, bytemuck::cast_slice(&locations));
            for slot in 0..locations.len() as u32 {
                self.record_location_of(rec, &self.shot, slot, QUANTITY_RADIOSITY, 0)?;
            }
        }
        Ok(())
    }

    /// Importance ≡ 1 on every element, none unshot: the id mode then picks as pr does (the
    /// equivalence the spec's validation asks for). For tests and comparisons.
    pub fn record_uniform_importance(&self, rec: &mut Recorder) {
        rec.fill_buffers(
            "radiosity uniform importance",
            &[
                (&self.importance, 1.0f32.to_bits()),
                (&self.importance_unshot, 0),
                (&self.importance_received, 0),
            ],
        );
    }

    /// The camera moved (id, pd): each element's importance received directly from it is
    /// replaced by what it receives now (pass B1; unseen elements lose theirs).
    pub fn record_camera_importance(&self, rec: &mut Recorder, camera: &CameraView) -> GpuResult<()> {
        self.record_view(rec, camera, VIEW_IMPORTANCE)
    }

    /// The simulated view changed (pd): mark the surfaces in `camera`'s view, and the table
    /// columns that now have receivers in view.
    /// `generation` numbers the change, so [`ShotState::may_deliver`] can tell when every
    /// delivery it made possible is done.
    pub fn record_visibility(&self, rec: &mut Recorder, camera: &CameraView, generation: u32) -> GpuResult<()> {
        rec.fill_buffer("radiosity view clear", &self.visible, 0);
        self.record_view(rec, camera, VIEW_VISIBILITY)?;
        self.table.record_scan(rec, &self.visible, generation)
    }

    /// Every surface in view (pd, after the widest simulated view): the whole table is due.
    pub fn record_visibility_everything(&self, rec: &mut Recorder, generation: u32) -> GpuResult<()> {
        rec.fill_buffer("radiosity view everything", &self.visible, 1);
        self.table.record_scan(rec, &self.visible, generation)
    }

    /// The camera's item buffer, then what its elements see of it.
    fn record_view(&self, rec: &mut Recorder, camera: &CameraView, flags: u32) -> GpuResult<()> {
        self.record_item_buffer(rec, 0, 0, ITEM_CAMERA, Some(camera))?;
        let element_count = self.elements.elements.len() as u32;
        rec.compute(&ComputePass {
            name: "radiosity view",
            pipeline: &self.view_pass,
            bindings: &[
                Binding::read(ids::RAD_ELEMENTS, &self.element_data),
                Binding::read(ids::RAD_SURFACES, &self.surfaces),
                Binding::write(ids::RAD_IMPORTANCE, &self.importance),
                Binding::write(ids::RAD_IMPORTANCE_UNSHOT, &self.importance_unshot),
                Binding::write(ids::RAD_IMPORTANCE_RECEIVED, &self.importance_received),
                Binding::write(ids::RAD_VISIBLE, &self.visible),
                Binding::image_read(ids::RAD_ITEM_IDS, &self.item_ids),
                Binding::image_read(ids::RAD_ITEM_DISTANCE, &self.item_distance),
            ],
            push: &ViewPush {
                camera: camera.clip.to_cols_array_2d(),
                eye: camera.eye.extend(1.0).to_array(),
                forward: camera.forward.extend(0.0).to_array(),
                element_count,
                resolution: self.options.resolution,
                bias: VISIBILITY_BIAS,
                scale: self.importance_scale,
                flags,
            },
            threads: self.element_threads(),
        })
    }

    /// One shot: in the id and pd modes first an importance shot, then the radiosity shot:
    /// select the shooter, place its locations, (pd) store the share of receivers out of view,
    /// draw and gather from each location, clear the shooter.
    pub fn record_shot(&self, rec: &mut Recorder) -> GpuResult<()> {
        let (select, flags) = match self.options.mode {
            Mode::Pr => (SELECT_POWER, 0),
            Mode::Id => (SELECT_IMPORTANCE_WEIGHTED, 0),
            Mode::Pd => (SELECT_IMPORTANCE_WEIGHTED, GATHER_RESTRICT),
        };
        if self.options.mode.follows_camera() {
            self.record_quantity_shot(rec, QUANTITY_IMPORTANCE, SELECT_IMPORTANCE_SHOOTER, 0)?;
        }
        self.record_quantity_shot(rec, QUANTITY_RADIOSITY, select, flags)
    }

    fn record_quantity_shot(&self, rec: &mut Recorder, quantity: u32, select: u32, flags: u32) -> GpuResult<()> {
        let surface_count = self.elements.surfaces.len() as u32;
        let shot = if quantity == QUANTITY_IMPORTANCE { &self.importance_shot } else { &self.shot };
        rec.compute(&ComputePass {
            name: "radiosity stats",
            pipeline: &self.stats_pass,
            bindings: &[
                Binding::read(ids::RAD_SURFACES, &self.surfaces),
                Binding::read(ids::RAD_ELEMENTS, &self.element_data),
                Binding::read(ids::RAD_UNSHOT, &self.unshot),
                Binding::read(ids::RAD_EMISSION_UNSHOT, &self.emission_unshot),
                Binding::read(ids::RAD_IMPORTANCE, &self.importance),
                Binding::read(ids::RAD_IMPORTANCE_UNSHOT, &self.importance_unshot),
                Binding::write(ids::RAD_STATS, &self.stats),
                Binding::write(ids::RAD_IMPORTANCE_STATS, &self.importance_stats),
            ],
            push: &StatsPush { surface_count },
            threads: [self.stats_groups * LINEAR_WORKGROUP, 1, 1],
        })?;
        rec.compute(&ComputePass {
            name: "radiosity select",
            pipeline: &self.select_pass,
            bindings: &[
                Binding::read(ids::RAD_SURFACES, &self.surfaces),
                Binding::read(ids::RAD_STATS, &self.stats),
                Binding::read(ids::RAD_IMPORTANCE_STATS, &self.importance_stats),
                Binding::read(ids::RAD_EMISSION_UNSHOT, &self.emission_unshot),
                Binding::write(ids::RAD_SHOT, shot),
            ],
            push: &SelectPush {
                reflectance_sum: self.reflectance_sum.extend(0.0).to_array(),
                surface_count,
                total_area: self.total_area.max(f32::MIN_POSITIVE),
                epsilon: self.options.epsilon,
                mode: select,
            },
            threads: [256, 1, 1],
        })?;
        rec.compute(&ComputePass {
            name: "radiosity locations",
            pipeline: &self.locations_pass,
            bindings: &[
                Binding::read(ids::RAD_SURFACES, &self.surfaces),
                Binding::read(ids::RAD_ELEMENTS, &self.element_data),
                Binding::read(ids::RAD_UNSHOT, &self.unshot),
                Binding::read(ids::RAD_EMISSION_UNSHOT, &self.emission_unshot),
                Binding::read(ids::RAD_IMPORTANCE_UNSHOT, &self.importance_unshot),
                Binding::read(ids::RAD_SHOT, shot),
                Binding::write(ids::RAD_LOCATIONS, &self.locations),
            ],
            push: &QuantityPush { quantity },
            threads: [self.slots * LINEAR_WORKGROUP, 1, 1],
        })?;
        if flags & GATHER_RESTRICT != 0 {
            self.table.record_store(rec, shot, &self.locations, &self.visible)?;
        }
        for slot in 0..self.slots {
            self.record_location_of(rec, shot, slot, quantity, flags)?;
        }
        rec.compute(&ComputePass {
            name: "radiosity finish",
            pipeline: &self.finish_pass,
            bindings: &[
                Binding::read(ids::RAD_SURFACES, &self.surfaces),
                Binding::read(ids::RAD_SHOT, shot),
                Binding::write(ids::RAD_UNSHOT, &self.unshot),
                Binding::write(ids::RAD_EMISSION_UNSHOT, &self.emission_unshot),
                Binding::write(ids::RAD_IMPORTANCE_UNSHOT, &self.importance_unshot),
            ],
            push: &QuantityPush { quantity },
            threads: [self.elements.largest_grid(), 1, 1],
        })
    }

    /// Up to `count` deliveries from the stored table (pd, §6.5): each picks the next column
    /// with entries for receivers in view, draws its location's item buffer, and shoots each
    /// such receiver its own entry. A delivery with nothing pending costs only empty passes.
    pub fn record_deliveries(&self, rec: &mut Recorder, count: u32) -> GpuResult<()> {
        if self.options.mode != Mode::Pd {
            return Ok(());
        }
        for _ in 0..count {
            self.table.record_pick(rec, &self.locations, &self.shot)?;
            self.record_location_of(rec, &self.shot, 0, QUANTITY_RADIOSITY, GATHER_DELIVER)?;
            self.table.record_spent(rec, &self.visible)?;
        }
        Ok(())
    }

    /// Copy the shot state where [`Solver::last_state`] reads it.
    pub fn record_state_copy(&self, rec: &mut Recorder) {
        rec.copy_buffer("radiosity state copy", &self.shot, &self.shot_copy, self.shot.size);
        rec.host_read(&self.shot_copy);
    }

    /// The state as the most recent finished frame left it (without waiting).
    pub fn last_state(&self) -> ShotState {
        self.shot_copy.mapped_value().unwrap_or_default()
    }

    /// Threads of a pass with one per element, in rows of workgroups (the shaders rebuild the
    /// element index from both dimensions).
    fn element_threads(&self) -> [u32; 3] {
        let elements = self.elements.elements.len() as u32;
        rows_of_workgroups(elements.div_ceil(LINEAR_WORKGROUP), LINEAR_WORKGROUP)
    }

    /// The item buffer of `slot`: one stereographic pass, five hemicube faces, or the camera.
    fn record_item_buffer(
        &self,
        rec: &mut Recorder,
        slot: u32,
        face: u32,
        projection: u32,
        camera: Option<&CameraView>,
    ) -> GpuResult<()> {
        rec.raster(&RasterPass {
            name: "radiosity item buffer",
            pipeline: &self.item_pass,
            bindings: &[
                Binding::read(ids::RAD_LOCATIONS, &self.locations),
                Binding::texels(ids::RAD_ITEM_VERTICES, &self.item_vertices),
                Binding::texels(ids::RAD_ITEM_TRIANGLES, &self.item_triangles),
            ],
            push: &ItemPush {
                camera: camera.map_or([[0.0; 4]; 4], |c| c.clip.to_cols_array_2d()),
                eye: camera.map_or([0.0; 4], |c| c.eye.extend(1.0).to_array()),
                slot,
                face,
                projection,
                far: self.far,
            },
            color: &[
                (&self.item_ids, face, [0.0; 4]),
                (&self.item_distance, face, [f32::MAX; 4]),
            ],
            depth: Some((&self.item_depth, face)),
            draw: Draw::Vertices(self.item_vertex_count),
            keep_contents: false,
        })
    }

    /// Draw the item buffer of location `slot` and gather from it into every element.
    fn record_location_of(
        &self,
        rec: &mut Recorder,
        shot: &Buffer,
        slot: u32,
        quantity: u32,
        flags: u32,
    ) -> GpuResult<()> {
        if self.options.hemicube {
            for face in 0..5 {
                self.record_item_buffer(rec, slot, face, ITEM_HEMICUBE, None)?;
            }
        } else {
            self.record_item_buffer(rec, slot, 0, ITEM_STEREOGRAPHIC, None)?;
        }
        let element_count = self.elements.elements.len() as u32;
        let [table, delivery] = self.table.gather_bindings();
        rec.compute(&ComputePass {
            name: "radiosity gather",
            pipeline: &self.gather_pass,
            bindings: &[
                Binding::texels(ids::RAD_ELEMENTS, &self.element_data),
                Binding::texels(ids::RAD_SURFACES, &self.surfaces),
                Binding::read(ids::RAD_SHOT, shot),
                Binding::read(ids::RAD_LOCATIONS, &self.locations),
                Binding::write(ids::RAD_UNSHOT, &self.unshot),
                Binding::write(ids::RAD_DIRECT, &self.direct),
                Binding::write(ids::RAD_INDIRECT, &self.indirect),
                Binding::write(ids::RAD_IMPORTANCE, &self.importance),
                Binding::write(ids::RAD_IMPORTANCE_UNSHOT, &self.importance_unshot),
                Binding::read(ids::RAD_VISIBLE, &self.visible),
                table,
                delivery,
                Binding::image_read(ids::RAD_ITEM_IDS, &self.item_ids),
                Binding::image_read(ids::RAD_ITEM_DISTANCE, &self.item_distance),
            ],
            push: &GatherPush {
                slot,
                element_count,
                hemicube: u32::from(self.options.hemicube),
                resolution: self.options.resolution,
                bias: VISIBILITY_BIAS,
                quantity,
                flags,
                surface_count: self.elements.surfaces.len() as u32,
            },
            threads: self.element_threads(),
        })
    }

    /// What the display reads.
    pub fn display_bindings(&self) -> [Binding<'_>; 4] {
        [
            Binding::texels(ids::RAD_SURFACES, &self.surfaces),
            Binding::texels(ids::RAD_ELEMENTS, &self.element_data),
            Binding::texels(ids::RAD_INDIRECT, &self.indirect),
            Binding::read(ids::RAD_SHOT, &self.shot),
        ]
    }

    /// Direct and indirect irradiance per element, read back (waits for the GPU).
    pub fn read_irradiance(&self, gpu: &Gpu) -> GpuResult<(Vec<Vec3>, Vec<Vec3>)> {
        let read = |buffer: &Buffer| -> GpuResult<Vec<Vec3>> {
            let bytes = gpu.read_buffer(buffer)?;
            Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)[..self.elements.elements.len()]
                .iter()
                .map(|v| Vec3::new(v[0], v[1], v[2]))
                .collect())
        };
        Ok((read(&self.direct)?, read(&self.indirect)?))
    }

    /// Which surfaces are in the simulated view (pd), read back (waits for the GPU).
    pub fn read_visible(&self, gpu: &Gpu) -> GpuResult<Vec<bool>> {
        let bytes = gpu.read_buffer(&self.visible)?;
        Ok(bytemuck::cast_slice::<u8, u32>(&bytes)[..self.elements.surfaces.len()]
            .iter()
            .map(|&v| v != 0)
            .collect())
    }

    /// The shot state, read back (waits for the GPU).
    pub fn read_state(&self, gpu: &Gpu) -> GpuResult<ShotState> {
        let bytes = gpu.read_buffer(&self.shot)?;
        Ok(bytemuck::pod_read_unaligned(&bytes[..std::mem::size_of::<ShotState>()]))
    }
}

/// Workgroups of the stats pass for `surface_count` surfaces, one a subgroup of `subgroup_size`
/// lanes: enough for each surface its own subgroup, at most [`MAX_WORKGROUPS_X`].
fn stats_workgroups(surface_count: u32, subgroup_size: u32) -> u32 {
    let per_group = (LINEAR_WORKGROUP / subgroup_size.max(1)).max(1);
    surface_count.div_ceil(per_group).clamp(1, MAX_WORKGROUPS_X)
}

/// A punctual light as one or two hemispheres of shooting locations: a spot (at most 90°)
/// around its axis, a point light as two opposite hemispheres.
fn light_locations(light: &Light) -> Vec<GpuLocation> {
    let (cos_outer, cos_inner) = light.cone_cosines();
    let axis = light.axis().map_or(Vec3::Y, |a| a.normalize_or(Vec3::Y));
    let hemispheres: Vec<Vec3> = match light.kind {
        LightKind::Point => vec![Vec3::Y, -Vec3::Y],
        _ => vec![axis],
    };
    hemispheres
        .into_iter()
        .map(|n| GpuLocation {
            position_area: light.position.extend(1.0).to_array(),
            normal_kind: n.extend(LOCATION_LIGHT).to_array(),
            emitted: light.intensity().extend(cos_inner).to_array(),
            reflected: axis.extend(cos_outer).to_array(),
        })
        .collect()
}

/// Triangles with no edge longer than this fraction of the scene's diagonal are not split
/// further (their projected edges bend little; a detailed mesh keeps its triangle count).
const ITEM_SPLIT_EDGE: f32 = 0.05;

/// The item-buffer mesh: every large triangle split 1-to-4 up to `level` times (so the
/// stereographic projection's straight edges stay close to its curves), each with the surfaces
/// (+1) of its patch's front and back, `ITEM_UNREACHED` for a side without one.
fn item_mesh(scene: &Scene, elements: &Elements, level: u32) -> (Vec<[f32; 4]>, Vec<[u32; 4]>) {
    const ITEM_UNREACHED: u32 = u32::MAX;
    let (lo, hi) = scene.mesh.bounds();
    let split_edge = ITEM_SPLIT_EDGE * (hi - lo).length();
    let large = |[a, b, c]: &[Vec3; 3]| {
        (b - a).length().max((c - b).length()).max((a - c).length()) > split_edge
    };
    let mut vertices = Vec::new();
    let mut sides = Vec::new();
    for t in 0..scene.mesh.triangle_count() {
        let patch = elements.triangle_patch[t] as usize;
        let id = |s: u32| if s == NO_SURFACE { ITEM_UNREACHED } else { s + 1 };
        let [front, back] = elements.patch_surfaces[patch].map(id);
        let mut triangles = vec![scene.mesh.triangle(t)];
        for _ in 0..level {
            triangles = triangles
                .into_iter()
                .flat_map(|t| {
                    if !large(&t) {
                        return vec![t];
                    }
                    let [a, b, c] = t;
                    let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
                    vec![[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
                })
                .collect();
        }
        for corners in triangles {
            vertices.extend(corners.map(|c| c.extend(1.0).to_array()));
            sides.push([front, back, 0, 0]);
        }
    }
    (vertices, sides)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stats_pass_gives_every_surface_a_subgroup_up_to_the_dispatch_limit() {
        // lavapipe's 8 lanes: 8 surfaces a workgroup of 64.
        assert_eq!(stats_workgroups(12_815, 8), 1602);
        assert_eq!(stats_workgroups(8, 8), 1);
        assert_eq!(stats_workgroups(9, 8), 2);
        // A subgroup as wide as the workgroup, or wider: one surface a workgroup.
        assert_eq!(stats_workgroups(30, 64), 30);
        assert_eq!(stats_workgroups(30, 128), 30);
        // No surfaces still dispatches one workgroup (its subgroups find nothing to do), and
        // past the limit the subgroups stride over the rest.
        assert_eq!(stats_workgroups(0, 32), 1);
        assert_eq!(stats_workgroups(10_000_000, 32), MAX_WORKGROUPS_X);
    }
}
