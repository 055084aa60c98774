//! The cache's GPU state and passes: the record buffer and counters, the hemisphere images of a
//! round's new records, the constant tables, each view's splat buffer and tile candidates, and
//! the recording of a view's placement rounds, splats and normalisation.

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::bindings as ids;
use super::records::{CacheState, GpuRecord};
use super::tables::{HALF_WIDTH, Tables};
use super::{CacheSettings, Placement};
use crate::gi::{FrameContext, PixelPass};
use crate::reference::Bounces;
use crate::gpu::{
    Depth,
    Binding, Draw, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuError, GpuResult, Image,
    ImageDesc, RasterPass, RasterPipeline, RasterPipelineDesc, Recorder, Specialization,
};
use crate::render::targets::View;
use crate::scene::Scene;
use crate::shaders;

/// Tile sides of the three rounds of tile placement (spec 003 §17 mode B).
pub const TILE_ROUNDS: [u32; 3] = [32, 16, 8];
/// A record's zone a·R spans at least and at most this many view pixels where it was placed.
pub const ZONE_PIXELS: [f32; 2] = [3.0, 64.0];
/// Size of a `VkDrawIndirectCommand`.
const DRAW_COMMAND_BYTES: u64 = 16;

/// The splat's normalisation, a per-pixel pass, by its name in the profile.
pub const NORMALISE: &str = "ic normalise";

/// What the normalisation must move and compute at the ideal. At a covered pixel: whether a
/// surface covers it (the depth, 4 B), the splat's weighted sums (16 B), the albedo (8 B), the
/// HDR pixel read and written (16 B each); at a background pixel the depth. Flops: the weight's
/// test 1, the sums' mean over pi (one reciprocal with 1/pi folded in, 3 products) 4, the
/// albedo's products 3, the sum 3. (The splat itself is work per record and its footprint, not
/// per pixel: it states no per-pixel bound.)
pub fn normalise_pass() -> PixelPass {
    PixelPass {
        pass: NORMALISE,
        bytes_per_pixel: 4.0 + 16.0 + 8.0 + 16.0 + 16.0,
        flops_per_pixel: 1.0 + 4.0 + 3.0 + 3.0,
        with_direct_lighting: false,
        background_bytes: Some(4.0),
    }
}

/// Format of the splat buffer: Σ w E' (rgb), Σ w.
const SPLAT_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

crate::push_constants! {
    struct SelectPush {
        size: [u32; 2],
        tile: [u32; 2],
        tiles_x: u32,
        accuracy: f32,
        scan: u32,
    }
}

crate::push_constants! {
    struct AppendPush {
        eye: [f32; 4],
        size: [u32; 2],
        tiles: u32,
        batch: u32,
        capacity: u32,
        generation: u32,
        scene_vertices: u32,
    }
}

crate::push_constants! {
    struct HemispherePush {
        slot: u32,
        near: f32,
        far: f32,
        half_width: f32,
        light_count: u32,
        accuracy: f32,
        smooth_weight: f32,
        normal_factor: f32,
    }
}

crate::push_constants! {
    struct BouncePush {
        generation: u32,
        bounces: u32,
        batch: u32,
        scene_vertices: u32,
    }
}

crate::push_constants! {
    struct ReducePush {
        resolution: u32,
        accuracy: f32,
        min_zone_pixels: f32,
        max_zone_pixels: f32,
    }
}

crate::push_constants! {
    struct SplatPush {
        view_projection: [[f32; 4]; 4],
        size: [u32; 2],
        round_only: u32,
        accuracy: f32,
        smooth_weight: f32,
        normal_factor: f32,
        generation: u32,
    }
}

crate::push_constants! {
    struct NormalisePush {
        size: [u32; 2],
    }
}

struct Pipelines {
    select: ComputePipeline,
    append: ComputePipeline,
    hemisphere: RasterPipeline,
    reduce: ComputePipeline,
    splat: RasterPipeline,
    normalise: ComputePipeline,
    bounce: ComputePipeline,
    snapshot: ComputePipeline,
}

/// What a view keeps: its splat buffer and one candidate slot per tile of the smallest tiles.
pub struct ViewState {
    pub splat: Image,
    candidates: Buffer,
}

pub struct Passes {
    pipelines: Pipelines,
    pub records: Buffer,
    pub state: Buffer,
    /// The previous bounce's records, which light the hemispheres of the next (same layout).
    pub previous: Buffer,
    /// The hemisphere slots' indirect draws (draws.glsl).
    draws: Buffer,
    state_copy: Buffer,
    tables: Buffer,
    /// The hemispheres of one round's new records, one layer each.
    pub hemisphere: Image,
    hemisphere_depth: Image,
    /// Records one round adds at most (the hemisphere image's layers).
    batch: u32,
    pub views: Vec<ViewState>,
    /// The hemisphere camera's offset above the record (and near plane), and its far plane.
    near: f32,
    far: f32,
    /// The generation of records the passes use (the state buffer starts at 0, the passes at
    /// 1); a new generation empties the cache from the next pass on, in whichever view.
    generation: u32,
}

impl Passes {
    pub fn new(gpu: &Gpu, scene: &Scene, settings: &CacheSettings) -> anyhow::Result<Passes> {
        if !gpu.supports_format(SPLAT_FORMAT, vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND) {
            return Err(GpuError::Setup(format!(
                "irradiance-cache: {} cannot blend into {SPLAT_FORMAT:?} attachments, which the splat needs",
                gpu.info.name
            ))
            .into());
        }
        gpu.info.require_compute_subgroup_arithmetic(
            "irradiance-cache",
            "its reduction sums each hemisphere in subgroups",
        )?;
        let none = Specialization::new();
        let compute = |name: &str, spirv: &[u8]| ComputePipeline::new(gpu, name, spirv, &none);
        let pipelines = Pipelines {
            select: compute("ic select", shaders::GI_IRRADIANCE_CACHE_SELECT_COMP)?,
            append: compute("ic append", shaders::GI_IRRADIANCE_CACHE_APPEND_COMP)?,
            reduce: compute("ic reduce", shaders::GI_IRRADIANCE_CACHE_REDUCE_COMP)?,
            normalise: compute(NORMALISE, shaders::GI_IRRADIANCE_CACHE_NORMALISE_COMP)?,
            bounce: compute("ic bounce", shaders::GI_IRRADIANCE_CACHE_BOUNCE_COMP)?,
            snapshot: compute("ic snapshot", shaders::GI_IRRADIANCE_CACHE_SNAPSHOT_COMP)?,
            hemisphere: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: "ic hemisphere",
                    vertex: shaders::GI_IRRADIANCE_CACHE_HEMISPHERE_VERT,
                    fragment: Some(shaders::GI_IRRADIANCE_CACHE_HEMISPHERE_FRAG),
                    color_formats: &[vk::Format::R32G32B32A32_SFLOAT],
                    depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                    depth_bias: None,
                    additive_blend: false,
                    conservative: false,
                    specialization: &crate::scene::gpu::texture_specialization(scene),
                },
            )?,
            splat: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: "ic splat",
                    vertex: shaders::GI_IRRADIANCE_CACHE_SPLAT_VERT,
                    fragment: Some(shaders::GI_IRRADIANCE_CACHE_SPLAT_FRAG),
                    color_formats: &[SPLAT_FORMAT],
                    depth: None,
                    depth_bias: None,
                    additive_blend: true,
                    conservative: false,
                    specialization: &none,
                },
            )?,
        };
        let batch = match settings.placement {
            Placement::Scan => 1,
            Placement::Tiles => settings.per_frame.div_ceil(TILE_ROUNDS.len() as u32),
        };
        let r = settings.hemisphere_size;
        let layered = |name: &str, format: vk::Format, usage: vk::ImageUsageFlags| {
            gpu.create_image(&ImageDesc {
                layers: batch,
                array: true,
                ..ImageDesc::new_2d(name, format, r, r, usage)
            })
        };
        let hemisphere = layered(
            "ic hemispheres",
            vk::Format::R32G32B32A32_SFLOAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
        )?;
        let hemisphere_depth = layered(
            "ic hemisphere depth",
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        )?;
        let tables = Tables::new(r as usize, settings.coverage);
        let texels = tables.gpu_texels();
        let record_bytes = std::mem::size_of::<GpuRecord>() as u64;
        let state_bytes = std::mem::size_of::<CacheState>() as u64;
        let diagonal = (scene.bounds_max - scene.bounds_min).length().max(1e-6);
        let passes = Passes {
            pipelines,
            records: gpu.create_buffer(&BufferDesc::storage(
                "ic records",
                u64::from(settings.capacity) * record_bytes,
            ))?,
            state: gpu.create_buffer(&BufferDesc::storage("ic state", state_bytes))?,
            previous: gpu.create_buffer(&BufferDesc::storage(
                "ic previous bounce",
                u64::from(settings.capacity) * record_bytes,
            ))?,
            draws: gpu.create_buffer(&BufferDesc {
                usage: vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_DST,
                ..BufferDesc::storage(
                    "ic hemisphere draws",
                    u64::from(batch) * DRAW_COMMAND_BYTES,
                )
            })?,
            state_copy: gpu.create_buffer(&BufferDesc {
                name: "ic state (host copy)",
                size: state_bytes,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
                texels: None,
            })?,
            // Two RGBA32F texels a hemisphere texel (reduce.comp).
            tables: gpu.upload_texel_items(
                "ic hemisphere tables",
                texels.len(),
                vk::Format::R32G32B32A32_SFLOAT,
                |i| texels[i],
            )?,
            hemisphere,
            hemisphere_depth,
            batch,
            views: Vec::new(),
            near: diagonal * 1e-4,
            far: diagonal * 2.0,
            generation: 1,
        };
        gpu.one_shot(|rec| {
            rec.fill_buffers("ic start", &[(&passes.state, 0), (&passes.draws, 0)]);
            Ok(())
        })?;
        Ok(passes)
    }

    /// The generation of records the passes keep (the counters' `generation` once a pass ran).
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// Empty the cache (lights or geometry changed): the next pass that reads it, in any view,
    /// finds it empty.
    pub fn empty(&mut self) {
        self.generation = self.generation.wrapping_add(1).max(1);
    }

    /// Copy the counters where [`Passes::last_state`] reads them.
    pub fn record_state_copy(&self, rec: &mut Recorder) {
        rec.copy_buffer("ic state copy", &self.state, &self.state_copy, self.state.size);
        rec.host_read(&self.state_copy);
    }

    /// The counters as the most recent finished frame left them (without waiting).
    pub fn last_state(&self) -> CacheState {
        self.state_copy.mapped_value().unwrap_or_default()
    }

    /// Make view `index`'s splat buffer and candidate slots fit the view.
    fn fit_view(&mut self, gpu: &Gpu, view: &View, index: usize) -> GpuResult<()> {
        let (w, h) = (view.width(), view.height());
        let fits = self
            .views
            .get(index)
            .is_some_and(|v| v.splat.width() == w && v.splat.height() == h);
        if fits {
            return Ok(());
        }
        let smallest = TILE_ROUNDS[TILE_ROUNDS.len() - 1];
        let tiles = u64::from(w.div_ceil(smallest)) * u64::from(h.div_ceil(smallest));
        let state = ViewState {
            splat: gpu.create_image(&ImageDesc::new_2d(
                "ic splat",
                SPLAT_FORMAT,
                w,
                h,
                vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::STORAGE
                    | vk::ImageUsageFlags::TRANSFER_SRC,
            ))?,
            candidates: gpu.create_buffer(&BufferDesc::storage("ic candidates", tiles * 4))?,
        };
        if index < self.views.len() {
            self.views[index] = state;
        } else {
            self.views.push(state);
        }
        Ok(())
    }

    /// A view's frame: splat every record, then place records where the view lacks them.
    pub fn record_view(
        &mut self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        index: usize,
        settings: &CacheSettings,
    ) -> GpuResult<()> {
        let view = &ctx.views[index];
        self.fit_view(rec.gpu(), view, index)?;
        self.record_splat(rec, view, index, settings, false)?;
        match settings.placement {
            Placement::Tiles => {
                for tile in TILE_ROUNDS {
                    self.record_round(rec, ctx, index, settings, [tile, tile], false)?;
                }
            }
            Placement::Scan => {
                for _ in 0..settings.per_frame {
                    let whole = [view.width(), view.height()];
                    self.record_round(rec, ctx, index, settings, whole, true)?;
                }
            }
        }
        Ok(())
    }

    /// One round: find the uncovered pixels (one per tile), add records there, render and
    /// reduce their hemispheres, splat them.
    fn record_round(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        index: usize,
        settings: &CacheSettings,
        tile: [u32; 2],
        scan: bool,
    ) -> GpuResult<()> {
        let view = &ctx.views[index];
        let state = &self.views[index];
        let g = &view.gbuffer;
        let size = [view.width(), view.height()];
        let tiles = [size[0].div_ceil(tile[0]), size[1].div_ceil(tile[1])];
        let accuracy = settings.weighting.accuracy as f32;
        rec.compute(&ComputePass {
            name: "ic select",
            pipeline: &self.pipelines.select,
            bindings: &[
                Binding::image_read(ids::IC_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::IC_SPLAT, &state.splat),
                Binding::write(ids::IC_CANDIDATES, &state.candidates),
            ],
            push: &SelectPush {
                size,
                tile,
                tiles_x: tiles[0],
                accuracy,
                scan: u32::from(scan),
            },
            threads: [tiles[0] * ids::IC_SELECT_WORKGROUP, tiles[1], 1],
        })?;
        let view_projection = view.eye.view_projection;
        // World size of a pixel per unit of distance: 2 tan(fov/2) / height, from the
        // projection's y row.
        let pixel_angle = 2.0 / (view_projection.row(1).truncate().length() * size[1] as f32);
        rec.compute(&ComputePass {
            name: "ic append",
            pipeline: &self.pipelines.append,
            bindings: &[
                Binding::image_read(ids::IC_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::IC_GBUFFER_NORMAL, &g.normal),
                Binding::read(ids::IC_CANDIDATES, &state.candidates),
                Binding::write(ids::IC_RECORDS, &self.records),
                Binding::write(ids::IC_STATE, &self.state),
                Binding::write(ids::IC_DRAWS, &self.draws),
            ],
            push: &AppendPush {
                eye: view.eye.position.extend(pixel_angle).to_array(),
                size,
                tiles: tiles[0] * tiles[1],
                batch: self.batch,
                capacity: settings.capacity,
                generation: self.generation,
                scene_vertices: ctx.scene.vertex_count,
            },
            threads: [1, 1, 1],
        })?;
        self.record_hemispheres(rec, ctx, settings)?;
        self.record_reduce(rec, settings)?;
        self.record_splat(rec, view, index, settings, true)
    }

    /// Rounds of the multiple-bounce refresh (bounce.comp): past the first bounce, records are
    /// recomputed from hemispheres lit by the snapshot of the previous bounce, as many a frame as
    /// placement may add.
    pub fn record_refresh(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        settings: &CacheSettings,
    ) -> GpuResult<()> {
        for _ in 0..settings.per_frame.div_ceil(self.batch) {
            rec.compute(&ComputePass {
                name: "ic bounce",
                pipeline: &self.pipelines.bounce,
                bindings: &[
                    Binding::read(ids::IC_RECORDS, &self.records),
                    Binding::read(ids::IC_PREVIOUS, &self.previous),
                    Binding::write(ids::IC_STATE, &self.state),
                    Binding::write(ids::IC_DRAWS, &self.draws),
                ],
                push: &BouncePush {
                    generation: self.generation,
                    bounces: match settings.bounces {
                        Bounces::Limited(n) => n,
                        Bounces::Unlimited => 0,
                    },
                    batch: self.batch,
                    scene_vertices: ctx.scene.vertex_count,
                },
                threads: [1, 1, 1],
            })?;
            rec.compute(&ComputePass {
                name: "ic snapshot",
                pipeline: &self.pipelines.snapshot,
                bindings: &[
                    Binding::read(ids::IC_RECORDS, &self.records),
                    Binding::write(ids::IC_PREVIOUS, &self.previous),
                    Binding::read(ids::IC_STATE, &self.state),
                ],
                push: &(),
                threads: [settings.capacity, 1, 1],
            })?;
            self.record_hemispheres(rec, ctx, settings)?;
            self.record_reduce(rec, settings)?;
        }
        Ok(())
    }

    /// The records `[first, end)` of the cache state from their hemispheres (layer k: record
    /// first + k).
    pub fn record_reduce(&self, rec: &mut Recorder, settings: &CacheSettings) -> GpuResult<()> {
        rec.compute(&ComputePass {
            name: "ic reduce",
            pipeline: &self.pipelines.reduce,
            bindings: &[
                Binding::image_read(ids::IC_HEMISPHERE, &self.hemisphere),
                Binding::texels(ids::IC_TABLES, &self.tables),
                Binding::write(ids::IC_RECORDS, &self.records),
                Binding::read(ids::IC_STATE, &self.state),
            ],
            push: &ReducePush {
                resolution: settings.hemisphere_size,
                accuracy: settings.weighting.accuracy as f32,
                min_zone_pixels: ZONE_PIXELS[0],
                max_zone_pixels: ZONE_PIXELS[1],
            },
            threads: [ids::IC_WORKGROUP, self.batch, 1],
        })
    }

    /// Every hemisphere slot of the round (slots past the round's new records draw nothing:
    /// their indirect draws, written by the append or bounce pass, have no vertices).
    fn record_hemispheres(
        &self,
        rec: &mut Recorder,
        ctx: &FrameContext,
        settings: &CacheSettings,
    ) -> GpuResult<()> {
        let scene = ctx.scene;
        let w = &settings.weighting;
        for slot in 0..self.batch {
            rec.raster(&RasterPass {
                name: "ic hemisphere",
                pipeline: &self.pipelines.hemisphere,
                bindings: &[
                    Binding::read(ids::IC_VERTICES, &scene.vertices),
                    Binding::read(ids::IC_TRIANGLES, &scene.triangles),
                    Binding::read(ids::IC_RECORDS, &self.records),
                    Binding::read(ids::IC_STATE, &self.state),
                    Binding::read(ids::IC_MATERIALS, &scene.materials),
                    Binding::read(ids::IC_TEXTURES, &scene.textures),
                    Binding::read(ids::IC_LIGHTS, &scene.lights),
                    Binding::read(ids::IC_SHADOW_VIEWS, &scene.shadow_views),
                    Binding::sampled(ids::IC_SHADOW_MAP, ctx.shadow_map, ctx.shadow_sampler),
                    Binding::read(ids::IC_PREVIOUS, &self.previous),
                ],
                push: &HemispherePush {
                    slot,
                    near: self.near,
                    far: self.far,
                    half_width: HALF_WIDTH as f32,
                    light_count: scene.light_count,
                    accuracy: w.accuracy as f32,
                    smooth_weight: if w.smooth { 1.0 } else { 0.0 },
                    normal_factor: w.normal_factor as f32,
                },
                color: &[(&self.hemisphere, slot, [0.0; 4])],
                depth: Some((&self.hemisphere_depth, slot)),
                draw: Draw::Indirect {
                    buffer: &self.draws,
                    offset: u64::from(slot) * DRAW_COMMAND_BYTES,
                },
                keep_contents: false,
            })?;
        }
        Ok(())
    }

    /// Splat every record (clearing the buffer first) or only this round's (adding to it).
    fn record_splat(
        &self,
        rec: &mut Recorder,
        view: &View,
        index: usize,
        settings: &CacheSettings,
        round_only: bool,
    ) -> GpuResult<()> {
        let g = &view.gbuffer;
        let w = &settings.weighting;
        let quads = if round_only {
            self.batch
        } else {
            settings.capacity
        };
        rec.raster(&RasterPass {
            name: if round_only { "ic splat new" } else { "ic splat" },
            pipeline: &self.pipelines.splat,
            bindings: &[
                Binding::read(ids::IC_RECORDS, &self.records),
                Binding::read(ids::IC_STATE, &self.state),
                Binding::image_read(ids::IC_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::IC_GBUFFER_NORMAL, &g.normal),
            ],
            push: &SplatPush {
                view_projection: view.eye.view_projection.to_cols_array_2d(),
                size: [view.width(), view.height()],
                round_only: u32::from(round_only),
                accuracy: w.accuracy as f32,
                smooth_weight: if w.smooth { 1.0 } else { 0.0 },
                normal_factor: w.normal_factor as f32,
                generation: self.generation,
            },
            color: &[(&self.views[index].splat, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(6 * quads),
            keep_contents: round_only,
        })
    }

    /// Indirect radiance from the splat buffer into the view's HDR image ([`NORMALISE`]).
    pub fn record_normalise(&self, rec: &mut Recorder, view: &View, index: usize) -> GpuResult<()> {
        let g = &view.gbuffer;
        rec.compute(&ComputePass {
            name: NORMALISE,
            pipeline: &self.pipelines.normalise,
            bindings: &[
                Binding::image_read(ids::IC_GBUFFER_POSITION, &g.position),
                Binding::image_read(ids::IC_GBUFFER_ALBEDO, &g.albedo),
                Binding::image_read(ids::IC_SPLAT, &self.views[index].splat),
                Binding::image_write(ids::IC_HDR, &view.hdr),
            ],
            push: &NormalisePush {
                size: [view.width(), view.height()],
            },
            threads: [view.width(), view.height(), 1],
        })
    }
}
