//! The method's GPU state and passes: the address volume, the cache buffer and its counters,
//! the RSM and its VAL mip chain, and the recording of a frame's allocation (per view), VALs,
//! indirect dispatch, cache lighting, and apply (per view).
//!
//! Address volume and counters come in two sets, one per frame parity, so that every view
//! records the same passes (a CAVE's walls, the conformance check): a frame's light work, after
//! its allocations, copies the previous frame's counters for the host and empties that set for
//! the next frame.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;

use super::bindings as ids;
use super::cascades::Cascades;
use super::cost::APPLY;
use super::voxelizer::RasterVoxelizer;
use super::voxels::VoxelGrid;
use super::{Bands, VolumeSettings};
use crate::gi::FrameContext;
use crate::gi::shared::rsm::Rsm;
use crate::gpu::dispatch::rows_of_workgroups;
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Recorder,
    Specialization,
};
use crate::render::targets::{View, check_buffer, check_texel_buffer};
use crate::scene::Scene;
use crate::shader_shared::LINEAR_WORKGROUP;
use crate::shaders;

crate::push_constants! {
    struct AllocatePush {
        eye_side: [f32; 4],
        size: [u32; 2],
        cascade_count: u32,
        resolution: u32,
        transition: f32,
        capacity: u32,
        stride: u32,
    }
}

crate::push_constants! {
    struct ArgsPush {
        capacity: u32,
    }
}

crate::push_constants! {
    struct ValsPush {
        rsm_size: u32,
        side: u32,
        block: u32,
        layers: u32,
    }
}

crate::push_constants! {
    struct ReducePush {
        source: u32,
        target: u32,
        side: u32,
        layers: u32,
    }
}

crate::push_constants! {
    struct LightPush {
        voxel_lo_size: [f32; 4],
        eye: [f32; 4],
        capacity: u32,
        stride: u32,
        coefficients: u32,
        side: u32,
        layers: u32,
        voxel_resolution: u32,
        voxel_levels: u32,
        shadow_level: u32,
        shadow_first: u32,
        shadows: u32,
        cone_steps: u32,
        specular_side: u32,
        specular_texels: u32,
    }
}

crate::push_constants! {
    struct VoxelizePush {
        lo_voxel: [f32; 4],
        resolution: u32,
        triangle_count: u32,
    }
}

crate::push_constants! {
    struct AdaptPush {
        side: u32,
        step: f32,
    }
}

crate::push_constants! {
    struct VoxelMipsPush {
        source: u32,
        target: u32,
        side: u32,
    }
}

crate::push_constants! {
    struct ApplyPush {
        eye_side: [f32; 4],
        size: [u32; 2],
        cascade_count: u32,
        resolution: u32,
        transition: f32,
        stride: u32,
        specular_side: u32,
        specular_texels: u32,
    }
}

/// The counters (rv.glsl `RvState`); the first three words are the lighting pass's
/// `VkDispatchIndirectCommand`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct RvState {
    pub groups: [u32; 3],
    /// Corners that asked for a cache this frame (those past the capacity were refused).
    pub requested: u32,
    /// Corners refused because the cache buffer was full.
    pub refused: u32,
    /// Corners the apply pass found without a cache: the allocation invariant says 0.
    pub missing: u32,
    /// Lit pixels beyond the last cascade, which get no cached light.
    pub beyond: u32,
    pad: u32,
}

impl RvState {
    /// Caches held this frame.
    pub fn held(&self, capacity: u32) -> u32 {
        self.requested.min(capacity)
    }
}

/// One level of the VAL mip chain: where it starts in the VAL buffer and its side per layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ValLevel {
    pub first: u32,
    pub side: u32,
}

struct Pipelines {
    allocate: ComputePipeline,
    args: ComputePipeline,
    vals: ComputePipeline,
    reduce: ComputePipeline,
    light: ComputePipeline,
    apply: ComputePipeline,
    voxelize: ComputePipeline,
    adapt: ComputePipeline,
    voxel_mips: ComputePipeline,
}

/// The voxelisation the shadow cones march through (spec 001 §4.6).
pub struct Voxels {
    pub grid: VoxelGrid,
    /// The binary target of the last voxelisation, one u32 per voxel of level 0.
    pub target: Buffer,
    /// The adapted occupancy, every level of the mip chain (f32).
    pub volume: Buffer,
    /// Frames of adaptation left since the geometry last changed.
    fade_left: u32,
    /// The raster voxelisation, where `--voxelizer` picks it (else the compute pass runs).
    pub raster: Option<RasterVoxelizer>,
}

pub struct Passes {
    pipelines: Pipelines,
    pub rsm: Rsm,
    /// Per frame parity (C·(N+1)³ corners): 0 no cache, index + 1, or the locked / refused
    /// marks.
    pub address: [Buffer; 2],
    /// Per cache: its position (w: cascade), then its SH coefficients (rgb), one vec4 each.
    pub caches: Buffer,
    /// Per cache: its hemisphere map of incoming light (one vec4 a texel; one texel in all
    /// when indirect specular is off).
    pub specular: Buffer,
    /// The counters, per frame parity.
    pub state: [Buffer; 2],
    state_copy: Buffer,
    /// The parity of the frame being recorded.
    pub parity: usize,
    pub voxels: Voxels,
    /// The VALs, every level of the chain, all layers.
    pub vals: Buffer,
    /// The chain's levels, the read level first.
    pub levels: Vec<ValLevel>,
    /// RSM texels per VAL side at the read level.
    pub block: u32,
    /// The cascades of the frame being recorded.
    pub cascades: Cascades,
    /// The first cascade's side in world units.
    pub first_side: f32,
}

/// Texels of one cache's specular map (0 when off).
pub fn specular_texels(side: u32) -> u32 {
    side * side
}

/// The apply pass's constants (apply.comp): the coefficients a cache keeps, whether indirect
/// specular is on, whether corners behind the surface are left out.
fn apply_specialization(settings: &VolumeSettings) -> Specialization {
    Specialization::new()
        .with_u32(0, settings.bands.coefficients())
        .with_u32(1, u32::from(settings.specular > 0))
        .with_u32(2, u32::from(settings.front_corners))
}

/// vec4s per cache: its position and its coefficients.
pub fn stride(bands: Bands) -> u32 {
    1 + bands.coefficients()
}

impl Passes {
    pub fn new(gpu: &Gpu, scene: &Scene, settings: &VolumeSettings) -> anyhow::Result<Passes> {
        let none = Specialization::new();
        let compute = |name: &str, spirv: &[u8]| ComputePipeline::new(gpu, name, spirv, &none);
        let pipelines = Pipelines {
            allocate: compute("rv allocate", shaders::GI_RADIANCE_VOLUMES_ALLOCATE_COMP)?,
            args: compute("rv args", shaders::GI_RADIANCE_VOLUMES_ARGS_COMP)?,
            vals: compute("rv vals", shaders::GI_RADIANCE_VOLUMES_VALS_COMP)?,
            reduce: compute("rv reduce", shaders::GI_RADIANCE_VOLUMES_REDUCE_COMP)?,
            light: compute("rv light", shaders::GI_RADIANCE_VOLUMES_LIGHT_COMP)?,
            apply: ComputePipeline::new(
                gpu,
                APPLY,
                shaders::GI_RADIANCE_VOLUMES_APPLY_COMP,
                &apply_specialization(settings),
            )?,
            voxelize: compute("rv voxelize", shaders::GI_RADIANCE_VOLUMES_VOXELIZE_COMP)?,
            adapt: compute("rv adapt", shaders::GI_RADIANCE_VOLUMES_ADAPT_COMP)?,
            voxel_mips: compute("rv voxel mips", shaders::GI_RADIANCE_VOLUMES_VOXEL_MIPS_COMP)?,
        };
        // Without shadows the lighting pass still binds a (one-voxel, empty) volume.
        let grid = VoxelGrid::fit(
            scene.bounds_min,
            scene.bounds_max,
            if settings.shadows { settings.voxels } else { 1 },
        );
        let target_bytes = grid.side(0).pow(3) as u64 * 4;
        let volume_bytes = grid.total() as u64 * 4;
        check_buffer(gpu, "the voxel target", target_bytes)?;
        check_buffer(gpu, "the voxel mip chain", volume_bytes)?;
        let raster = if settings.shadows {
            RasterVoxelizer::new(gpu, settings.voxelizer, &grid)?
        } else {
            None
        };
        let voxels = Voxels {
            raster,
            grid,
            target: gpu.create_buffer(&BufferDesc::storage("rv voxel target", target_bytes))?,
            volume: gpu.create_buffer(&BufferDesc::storage("rv voxels", volume_bytes))?,
            fade_left: 0,
        };
        let rsm = Rsm::new(gpu, scene, settings.rsm)?;
        let (block, levels) = val_chain(settings.rsm, rsm.layers, settings.val_budget);
        let val_total = levels.last().map_or(0, |l| l.first + l.side * l.side * rsm.layers);
        let val_bytes = u64::from(val_total) * 64;
        check_buffer(gpu, "the VAL mip chain", val_bytes)?;
        let corners = u64::from(settings.cascades) * u64::from(settings.resolution + 1).pow(3);
        check_buffer(gpu, "the cache address volume", corners * 4)?;
        // The apply pass reads the caches as texels (rv/apply.comp says why).
        let cache_bytes = u64::from(settings.capacity) * u64::from(stride(settings.bands)) * 16;
        check_texel_buffer(gpu, "the cache buffer", cache_bytes)?;
        let specular_bytes =
            u64::from(settings.capacity) * u64::from(specular_texels(settings.specular)) * 16;
        check_buffer(gpu, "the specular map buffer", specular_bytes)?;
        let first_side = first_cascade_side(scene, settings);
        let state_bytes = std::mem::size_of::<RvState>() as u64;
        let state_buffer = |name| {
            gpu.create_buffer(&BufferDesc {
                usage: vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_DST
                    | vk::BufferUsageFlags::TRANSFER_SRC,
                ..BufferDesc::storage(name, state_bytes)
            })
        };
        let passes = Passes {
            pipelines,
            rsm,
            address: [
                gpu.create_buffer(&BufferDesc::storage("rv address volume", corners * 4))?,
                gpu.create_buffer(&BufferDesc::storage("rv address volume", corners * 4))?,
            ],
            caches: gpu.create_buffer(&BufferDesc::storage_texels("rv caches", cache_bytes))?,
            specular: gpu.create_buffer(&BufferDesc::storage(
                "rv specular maps",
                specular_bytes.max(16),
            ))?,
            state: [state_buffer("rv state")?, state_buffer("rv state")?],
            state_copy: gpu.create_buffer(&BufferDesc {
                name: "rv state (host copy)",
                size: state_bytes,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
                texels: None,
            })?,
            parity: 0,
            voxels,
            vals: gpu.create_buffer(&BufferDesc::storage_texels("rv vals", val_bytes))?,
            levels,
            block,
            cascades: Cascades::around(
                scene.camera.position,
                settings.cascades as usize,
                settings.resolution,
                first_side,
                settings.transition,
            ),
            first_side,
        };
        gpu.one_shot(|rec| {
            rec.fill_buffers(
                "rv start",
                &[
                    (&passes.address[0], ids::RV_EMPTY),
                    (&passes.address[1], ids::RV_EMPTY),
                    (&passes.state[0], 0),
                    (&passes.state[1], 0),
                    (&passes.voxels.volume, 0),
                ],
            );
            Ok(())
        })?;
        Ok(passes)
    }

    /// Bytes of GPU memory the method holds, by what for.
    pub fn memory(&self) -> Vec<(&'static str, u64)> {
        // Position and flux 16 bytes a texel, the normal 8, one depth layer 4.
        let texels = u64::from(self.rsm.size).pow(2);
        let rsm = texels * (40 * u64::from(self.rsm.layers) + 4);
        vec![
            ("caches", self.caches.size),
            ("specular maps", self.specular.size),
            ("address volumes", 2 * self.address[0].size),
            ("VAL chain", self.vals.size),
            ("voxels", self.voxels.target.size + self.voxels.volume.size),
            ("RSM", rsm),
        ]
    }

    /// VALs the caches are lit by each frame (the read level, every layer).
    pub fn val_count(&self) -> u32 {
        self.levels[0].side.pow(2) * self.rsm.layers
    }

    /// Place this frame's cascades around `eye` (on the host: the shaders derive them from
    /// the push constants).
    pub fn place(&mut self, eye: glam::Vec3, settings: &VolumeSettings) {
        self.cascades = Cascades::around(
            eye,
            settings.cascades as usize,
            settings.resolution,
            self.first_side,
            settings.transition,
        );
    }

    /// The push constants' cascade centre and first side.
    fn eye_side(&self) -> [f32; 4] {
        self.cascades.eye.extend(self.first_side).to_array()
    }

    /// Allocate the caches view `view`'s lit pixels need.
    pub fn record_allocate(
        &self,
        rec: &mut Recorder,
        view: &View,
        settings: &VolumeSettings,
    ) -> GpuResult<()> {
        rec.compute(&ComputePass {
            name: "rv allocate",
            pipeline: &self.pipelines.allocate,
            bindings: &[
                Binding::image_read(ids::RV_GBUFFER_POSITION, &view.gbuffer.position),
                Binding::write(ids::RV_ADDRESS, &self.address[self.parity]),
                Binding::write(ids::RV_CACHES, &self.caches),
                Binding::write(ids::RV_STATE, &self.state[self.parity]),
            ],
            push: &AllocatePush {
                eye_side: self.eye_side(),
                size: [view.width(), view.height()],
                cascade_count: settings.cascades,
                resolution: settings.resolution,
                transition: settings.transition,
                capacity: settings.capacity,
                stride: stride(settings.bands),
            },
            threads: [view.width(), view.height(), 1],
        })
    }

    /// The RSM, its VALs and their chain, the indirect dispatch and the cache lighting; then
    /// the previous frame's counters copied for the host and its set emptied for the next
    /// frame.
    pub fn record_light(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        settings: &VolumeSettings,
    ) -> GpuResult<()> {
        if settings.shadows {
            self.record_voxels(rec, ctx, settings)?;
        }
        self.rsm.record(rec, ctx)?;
        let layers = self.rsm.layers;
        let read = self.levels[0];
        rec.compute(&ComputePass {
            name: "rv vals",
            pipeline: &self.pipelines.vals,
            bindings: &[
                Binding::image_read(ids::RV_RSM_POSITION, &self.rsm.position),
                Binding::image_read(ids::RV_RSM_NORMAL, &self.rsm.normal),
                Binding::image_read(ids::RV_RSM_FLUX, &self.rsm.flux),
                Binding::read(ids::RV_SHADOW_VIEWS, &ctx.scene.shadow_views),
                Binding::write(ids::RV_VALS, &self.vals),
            ],
            push: &ValsPush {
                rsm_size: self.rsm.size,
                side: read.side,
                block: self.block,
                layers,
            },
            threads: [read.side, read.side, layers],
        })?;
        for (step, pair) in self.levels.windows(2).enumerate() {
            rec.in_step(step as u32 + 1, |rec| {
                rec.compute(&ComputePass {
                    name: "rv reduce",
                    pipeline: &self.pipelines.reduce,
                    bindings: &[Binding::write(ids::RV_VALS, &self.vals)],
                    push: &ReducePush {
                        source: pair[0].first,
                        target: pair[1].first,
                        side: pair[1].side,
                        layers,
                    },
                    threads: [pair[1].side, pair[1].side, layers],
                })
            })?;
        }
        rec.compute(&ComputePass {
            name: "rv args",
            pipeline: &self.pipelines.args,
            bindings: &[Binding::write(ids::RV_STATE, &self.state[self.parity])],
            push: &ArgsPush {
                capacity: settings.capacity,
            },
            threads: [1, 1, 1],
        })?;
        let grid = self.voxels.grid;
        let shadow = self.shadow_level(settings);
        rec.compute_indirect(
            &ComputePass {
                name: "rv light",
                pipeline: &self.pipelines.light,
                bindings: &[
                    Binding::write(ids::RV_CACHES, &self.caches),
                    Binding::write(ids::RV_SPECULAR, &self.specular),
                    Binding::texels(ids::RV_VALS, &self.vals),
                    Binding::read(ids::RV_STATE, &self.state[self.parity]),
                    Binding::read(ids::RV_VOXELS, &self.voxels.volume),
                    Binding::read(ids::RV_SHADOW_VIEWS, &ctx.scene.shadow_views),
                ],
                push: &LightPush {
                    voxel_lo_size: grid.min.extend(grid.voxel).to_array(),
                    eye: self.cascades.eye.extend(1.0).to_array(),
                    capacity: settings.capacity,
                    stride: stride(settings.bands),
                    coefficients: settings.bands.coefficients(),
                    side: read.side,
                    layers,
                    voxel_resolution: grid.resolution,
                    voxel_levels: grid.levels(),
                    shadow_level: shadow.0,
                    shadow_first: shadow.1.first,
                    shadows: u32::from(settings.shadows),
                    cone_steps: super::voxels::CONE_STEPS,
                    specular_side: settings.specular,
                    specular_texels: specular_texels(settings.specular),
                },
                threads: [0; 3],
            },
            &self.state[self.parity],
            0,
        )?;
        let previous = 1 - self.parity;
        let state = &self.state[previous];
        rec.copy_buffer("rv state copy", state, &self.state_copy, state.size);
        rec.host_read(&self.state_copy);
        rec.fill_buffers(
            "rv clear",
            &[(&self.address[previous], ids::RV_EMPTY), (state, 0)],
        );
        self.parity = previous;
        Ok(())
    }

    /// The chain level of the shadow cones' blocks (`--shadow-lod`, at most the chain's last)
    /// and that level.
    pub fn shadow_level(&self, settings: &VolumeSettings) -> (u32, ValLevel) {
        let level = settings.shadow_lod.min(self.levels.len() as u32 - 1);
        (level, self.levels[level as usize])
    }

    /// Mark the voxels every triangle touches in the binary target, by the raster pass where
    /// `--voxelizer` picked it, else by the compute pass (one thread per triangle).
    fn record_voxelize(&self, rec: &mut Recorder, ctx: &FrameContext) -> GpuResult<()> {
        let grid = &self.voxels.grid;
        let scene = ctx.scene;
        if let Some(raster) = &self.voxels.raster {
            let triangles = (&scene.vertices, &scene.triangles, scene.vertex_count);
            return raster.record(rec, triangles, grid, &self.voxels.target);
        }
        let triangles = scene.vertex_count / 3;
        let threads = rows_of_workgroups(triangles.div_ceil(LINEAR_WORKGROUP), LINEAR_WORKGROUP);
        rec.compute(&ComputePass {
            name: "rv voxelize",
            pipeline: &self.pipelines.voxelize,
            bindings: &[
                Binding::read(ids::RV_VERTICES, &scene.vertices),
                Binding::read(ids::RV_TRIANGLES, &scene.triangles),
                Binding::write(ids::RV_VOXEL_TARGET, &self.voxels.target),
            ],
            push: &VoxelizePush {
                lo_voxel: grid.min.extend(grid.voxel).to_array(),
                resolution: grid.resolution,
                triangle_count: triangles,
            },
            threads,
        })
    }

    /// Voxelise the scene again where its geometry changed, and move the occupancy toward it
    /// for `--voxel-fade` frames (at once on the method's first frame), mips included.
    fn record_voxels(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        settings: &VolumeSettings,
    ) -> GpuResult<()> {
        let grid = self.voxels.grid;
        let first = ctx.frame == 0;
        if first || ctx.changes.geometry {
            rec.fill_buffer("rv clear voxel target", &self.voxels.target, 0);
            self.record_voxelize(rec, ctx)?;
            self.voxels.fade_left = if first { 1 } else { settings.voxel_fade };
        }
        if self.voxels.fade_left == 0 {
            return Ok(());
        }
        let side = grid.side(0) as u32;
        rec.compute(&ComputePass {
            name: "rv adapt",
            pipeline: &self.pipelines.adapt,
            bindings: &[
                Binding::read(ids::RV_VOXEL_TARGET, &self.voxels.target),
                Binding::write(ids::RV_VOXELS, &self.voxels.volume),
            ],
            push: &AdaptPush {
                side,
                step: if first {
                    1.0
                } else {
                    1.0 / settings.voxel_fade as f32
                },
            },
            threads: [side, side, side],
        })?;
        for level in 1..grid.levels() {
            let side = grid.side(level) as u32;
            rec.in_step(level, |rec| {
                rec.compute(&ComputePass {
                    name: "rv voxel mips",
                    pipeline: &self.pipelines.voxel_mips,
                    bindings: &[Binding::write(ids::RV_VOXELS, &self.voxels.volume)],
                    push: &VoxelMipsPush {
                        source: grid.offset(level - 1) as u32,
                        target: grid.offset(level) as u32,
                        side,
                    },
                    threads: [side, side, side],
                })
            })?;
        }
        self.voxels.fade_left -= 1;
        Ok(())
    }

    /// Add view `view`'s cached indirect light to its HDR image (after the frame's light work,
    /// which flipped the parity: the set this frame allocated into is the other one).
    pub fn record_apply(
        &self,
        rec: &mut Recorder,
        view: &View,
        settings: &VolumeSettings,
    ) -> GpuResult<()> {
        let set = 1 - self.parity;
        let g = &view.gbuffer;
        rec.compute(&ComputePass {
            name: APPLY,
            pipeline: &self.pipelines.apply,
            bindings: &[
                Binding::image_read(ids::RV_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::RV_GBUFFER_NORMAL, &g.normal),
                Binding::image_read(ids::RV_GBUFFER_ALBEDO, &g.albedo),
                Binding::image_read(ids::RV_GBUFFER_SPECULAR, &g.specular),
                Binding::image_write(ids::RV_HDR, &view.hdr),
                Binding::read(ids::RV_ADDRESS, &self.address[set]),
                Binding::texels(ids::RV_CACHES, &self.caches),
                Binding::read(ids::RV_SPECULAR, &self.specular),
                Binding::write(ids::RV_STATE, &self.state[set]),
            ],
            push: &ApplyPush {
                eye_side: self.eye_side(),
                size: [view.width(), view.height()],
                cascade_count: settings.cascades,
                resolution: settings.resolution,
                transition: settings.transition,
                stride: stride(settings.bands),
                specular_side: settings.specular,
                specular_texels: specular_texels(settings.specular),
            },
            threads: [view.width(), view.height(), 1],
        })
    }

    /// The set (address volume, counters) the most recently recorded frame used.
    pub fn last_set(&self) -> usize {
        1 - self.parity
    }

    /// The counters of the frame before the most recent finished one (without waiting).
    pub fn last_state(&self) -> RvState {
        self.state_copy.mapped_value().unwrap_or_default()
    }
}

/// The first cascade's side: the last cascade reaches `settings.reach` times as far as the
/// scene's farthest point from its camera (max norm), with a cell to spare for the snapping.
pub fn first_cascade_side(scene: &Scene, settings: &VolumeSettings) -> f32 {
    let (lo, hi, eye) = (scene.bounds_min, scene.bounds_max, scene.camera.position);
    let reach = (eye - lo).abs().max((hi - eye).abs()).max_element().max(1e-6);
    let n = settings.resolution as f32;
    let last_side = 2.0 * reach * settings.reach * n / (n - 2.0);
    last_side / (1u32 << (settings.cascades - 1)) as f32
}

/// The VAL chain for an RSM of `size`² texels and `layers` layers: the read level is the finest
/// whose VALs over all layers number at most `budget` (or one VAL a layer), and the chain goes
/// on to one VAL a layer. Returns the read level's texels per VAL side and the levels.
pub fn val_chain(size: u32, layers: u32, budget: u32) -> (u32, Vec<ValLevel>) {
    let mut side = size;
    while side > 1 && u64::from(side).pow(2) * u64::from(layers) > u64::from(budget) {
        side /= 2;
    }
    let block = size / side;
    let mut levels = Vec::new();
    let mut first = 0;
    loop {
        levels.push(ValLevel { first, side });
        if side == 1 {
            break;
        }
        first += side * side * layers;
        side /= 2;
    }
    (block, levels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_read_level_fits_the_budget_and_the_chain_ends_at_one_val_a_layer() {
        let (block, levels) = val_chain(256, 1, 4096);
        assert_eq!(block, 4);
        assert_eq!(levels[0], ValLevel { first: 0, side: 64 });
        assert_eq!(levels.len(), 7);
        assert_eq!(levels[1], ValLevel { first: 4096, side: 32 });
        assert_eq!(levels.last().unwrap().side, 1);
        // 80 layers (16 area-light samples, 5 views each): 4x4 VALs a layer.
        let (block, levels) = val_chain(256, 80, 4096);
        assert_eq!((block, levels[0].side), (64, 4));
        // More layers than the budget: one VAL a layer.
        let (block, levels) = val_chain(64, 5000, 4096);
        assert_eq!((block, levels.len()), (64, 1));
    }
}
