//! LightWave's indirect shadows (spec 002 §2.3): depth maps rendered from a few VPLs of each
//! light's rig, all layers of one array, re-rendered every frame. Each camera sits on its VPL
//! and looks at the scene's centre (the thesis's code aimed at a point within one unit of the
//! origin, its room's centre) with the thesis's 125° field of view; square maps.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, Vec3};

use super::cpu::rig_axis;
use super::rig::Rig;
use crate::gi::FrameContext;
use crate::gpu::{
    Depth,
    Binding, Draw, Buffer, BufferDesc, Gpu, GpuResult, Image, ImageDesc, RasterPass, RasterPipeline,
    RasterPipelineDesc, Recorder,
};
use crate::render::targets::{MAX_RESOURCE_BYTES, check_texel_buffer};
use crate::scene::{Light, Scene};
use crate::shader_shared::{RASTER_TRIANGLES, RASTER_VERTICES};
use crate::shaders;

/// The thesis's field of view for every shadow camera (gluPerspective fovy 125°).
pub const FOV_DEG: f32 = 125.0;
/// Smallest and largest side of a map.
const MIN_SIDE: u32 = 16;
const MAX_SIDE: u32 = 8192;

crate::push_constants! {
    struct ShadowPush {
        view_projection: [[f32; 4]; 4],
    }
}

/// One map's camera as the gather reads it (five texels: `vpl_view` in
/// gi/lightwave/composite.glsl).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuView {
    view_projection: [[f32; 4]; 4],
    /// xyz the VPL, w = texel size per unit distance.
    eye_texel: [f32; 4],
}

/// The maps of every light's shadow-casting VPLs.
pub struct VplShadows {
    pipeline: RasterPipeline,
    /// Which VPLs of each rig cast shadows (indices into the rig).
    set: Vec<u32>,
    /// Texels along a side (fitted to the views on the first frame).
    pub side: u32,
    /// The side the shadow ratio asked for, when the memory limit made it smaller.
    pub clamped_from: Option<u32>,
    ratio: f32,
    image: Option<Image>,
    views: Buffer,
    /// The scene's centre and the length of its bounds' diagonal.
    centre: Vec3,
    extent: f32,
}

impl VplShadows {
    /// Maps for `set` of every one of `lights`' rigs; `ratio` × the largest view side each.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        lights: &[Light],
        set: Vec<u32>,
        ratio: f32,
    ) -> anyhow::Result<VplShadows> {
        let layers = (set.len() * lights.len()).max(1) as u32;
        crate::render::targets::check_layered_image(
            gpu,
            &format!("LightWave's {} VPL shadow map(s)", layers),
            (MIN_SIDE, layers, 4),
            "use fewer --lightwave-shadow-maps or fewer lights",
        )?;
        let pipeline = RasterPipeline::new(
            gpu,
            &RasterPipelineDesc {
                name: "lightwave shadow map",
                vertex: shaders::RASTER_SHADOW_VERT,
                fragment: None,
                color_formats: &[],
                depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                depth_bias: Some((1.25, 1.75)),
                additive_blend: false,
                conservative: false,
                specialization: &crate::gpu::Specialization::new(),
            },
        )?;
        // The gather reads the views as texels (gi/lightwave/composite.glsl says why).
        let view_bytes = u64::from(layers) * std::mem::size_of::<GpuView>() as u64;
        check_texel_buffer(gpu, "the VPL shadow views", view_bytes)?;
        let views = gpu.create_buffer(&BufferDesc::storage_texels("lightwave shadow views", view_bytes))?;
        let extent = (scene.bounds_max - scene.bounds_min).length().max(1e-3);
        Ok(VplShadows {
            pipeline,
            set,
            side: 0,
            clamped_from: None,
            ratio,
            image: None,
            views,
            centre: 0.5 * (scene.bounds_min + scene.bounds_max),
            extent,
        })
    }

    /// Maps per light.
    pub fn per_light(&self) -> u32 {
        self.set.len() as u32
    }

    /// Layers of the array (at least one).
    fn layers(&self, lights: usize) -> u32 {
        (self.set.len() * lights).max(1) as u32
    }

    /// The array the gather samples (made on the first frame, sized to its views).
    pub fn image(&self) -> Option<&Image> {
        self.image.as_ref()
    }

    pub fn views(&self) -> &Buffer {
        &self.views
    }

    /// Place every camera on its VPL and render the maps.
    pub fn record(&mut self, rec: &mut Recorder, ctx: &FrameContext, rig: &Rig) -> GpuResult<()> {
        if self.image.is_none() {
            self.make_image(rec.gpu(), ctx)?;
        }
        let views = self.cameras(ctx.raster_lights, rig);
        rec.update_buffer("lightwave shadow views", &self.views, bytemuck::cast_slice(&views));
        let (Some(image), false) = (&self.image, self.set.is_empty()) else {
            return Ok(());
        };
        let s = ctx.scene;
        for (layer, view) in views.iter().enumerate() {
            let push = ShadowPush {
                view_projection: view.view_projection,
            };
            rec.in_layer(layer as u32, |rec| {
                rec.raster(&RasterPass {
                    name: "lightwave shadow map",
                    pipeline: &self.pipeline,
                    bindings: &[
                        Binding::read(RASTER_VERTICES, &s.vertices),
                        Binding::read(RASTER_TRIANGLES, &s.triangles),
                    ],
                    push: &push,
                    color: &[],
                    depth: Some((image, layer as u32)),
                    draw: Draw::Vertices(s.vertex_count),
                    keep_contents: false,
                })
            })?;
        }
        Ok(())
    }

    /// The array at `ratio` × the largest view side, made smaller if the memory limit says so.
    fn make_image(&mut self, gpu: &Gpu, ctx: &FrameContext) -> GpuResult<()> {
        let largest = ctx
            .views
            .iter()
            .map(|v| v.width().max(v.height()))
            .max()
            .unwrap_or(MIN_SIDE);
        let layers = self.layers(ctx.raster_lights.len());
        let wanted = ((largest as f32 * self.ratio).round() as u32)
            .clamp(MIN_SIDE, MAX_SIDE.min(gpu.info.max_image_dimension_2d));
        let limit = MAX_RESOURCE_BYTES.min(gpu.info.max_memory_allocation_size.max(1));
        let fits = ((limit / (4 * u64::from(layers))) as f64).sqrt() as u32;
        self.side = wanted.min(fits).max(MIN_SIDE);
        self.clamped_from = (self.side < wanted).then_some(wanted);
        self.image = Some(gpu.create_image(&ImageDesc {
            layers,
            array: true,
            ..ImageDesc::new_2d(
                "lightwave shadow maps",
                vk::Format::D32_SFLOAT,
                self.side,
                self.side,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            )
        })?);
        Ok(())
    }

    /// Every map's camera: per light, per VPL of the set.
    fn cameras(&self, lights: &[Light], rig: &Rig) -> Vec<GpuView> {
        let mut views: Vec<GpuView> = lights
            .iter()
            .flat_map(|light| {
                self.set.iter().map(move |&j| {
                    let vpl = rig.vpl(light.position.as_dvec3(), rig_axis(light), j);
                    self.camera(vpl.position.as_vec3(), vpl.direction.as_vec3())
                })
            })
            .collect();
        if views.is_empty() {
            views.push(GpuView::zeroed());
        }
        views
    }

    /// A camera at `eye` looking at the scene's centre (along `direction` when it sits there).
    fn camera(&self, eye: Vec3, direction: Vec3) -> GpuView {
        let extent = self.extent;
        let to_centre = self.centre - eye;
        let forward = if to_centre.length() > 1e-3 * extent {
            to_centre.normalize()
        } else {
            direction
        };
        let up = if forward.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
        let far = to_centre.length() + extent;
        let near = (extent * 1e-3).min(far * 0.01);
        let view = look_at_mat4(eye, eye + forward, up);
        let projection: Mat4 = vulkan::perspective(FOV_DEG.to_radians(), 1.0, near, far);
        let texel = 2.0 * (0.5 * FOV_DEG.to_radians()).tan() / self.side.max(1) as f32;
        GpuView {
            view_projection: (projection * view).to_cols_array_2d(),
            eye_texel: eye.extend(texel).to_array(),
        }
    }
}
