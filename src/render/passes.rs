//! The frame's own passes: shadow maps, the G-buffer, deferred direct lighting and tone mapping.
//! src/render/frame.rs calls them in order; GI methods add theirs between them.

use ash::vk;
use glam::Vec3;

use super::full_screen::{Blend, FullScreenShaders, Pixels, full_screen, full_screen_with};
use super::targets::{GBUFFER_DEPTH_FORMAT, GBUFFER_FORMATS, HDR_FORMAT, LDR_RENDER_FORMAT, View};
use crate::gpu::{
    Binding, ComputePass, ComputePipeline, Depth, Draw, Gpu, GpuResult, Image, PixelPasses,
    RasterPass, RasterPipeline, RasterPipelineDesc, Recorder, Sampler, Specialization,
};
use crate::scene::gpu::{SceneBuffers, shadow_view_ranges};
use crate::scene::{Light, Material, Scene};
use crate::shader_shared as ids;
use crate::shaders;

/// The frame's per-pixel passes' names in the profile.
pub const GBUFFER: &str = "g-buffer";
pub const DIRECT_LIGHTING: &str = "direct lighting";
pub const TONE_MAP: &str = "tone map";

crate::push_constants! {
    struct GBufferPush {
        view_projection: [[f32; 4]; 4],
        camera_position: [f32; 4],
    }
}

crate::push_constants! {
    struct ShadowPush {
        view_projection: [[f32; 4]; 4],
    }
}

crate::push_constants! {
    /// Direct lighting's push constants (raster/direct.glsl).
    pub struct LightingPush {
        camera_position: [f32; 4],
        size: [u32; 2],
        light_count: u32,
        include_direct: u32,
        first_view: [u32; MAX_SHARED_LIGHTS],
        view_count: [u32; MAX_SHARED_LIGHTS],
    }
}

/// A scene with at most this many rasterised lights is lit by direct lighting at constant
/// indices into its lights and shadow views (`SHARED_LIGHTS` in raster/lighting.comp), read once
/// for all pixels of a SIMD batch on lavapipe instead of lane by lane.
pub const MAX_SHARED_LIGHTS: usize = 8;

crate::push_constants! {
    struct TonemapPush {
        exposure_scale: f32,
    }
}

/// Which terms of direct lighting a scene's materials have at all.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialTerms {
    /// Some material emits.
    pub emissive: bool,
    /// Some material has a glossy lobe.
    pub glossy: bool,
}

impl MaterialTerms {
    pub fn of(scene: &Scene) -> MaterialTerms {
        let has = |term: fn(&Material) -> Vec3| {
            scene.materials.iter().any(|m| term(m).max_element() > 0.0)
        };
        MaterialTerms {
            emissive: has(|m| m.emission),
            glossy: has(|m| m.specular),
        }
    }
}

/// Direct lighting's two forms (raster/direct.glsl): the same radiance.
enum DirectLighting {
    /// A compute pass: any number of lights, read from their buffers.
    Compute(ComputePipeline),
    /// A fragment pass over a full-screen triangle whose vertex shader hands the shared lights
    /// and their views to the fragments as flat varyings: on lavapipe a render target's write
    /// costs less than an imageStore (docs/performance.md).
    Fragment(RasterPipeline),
}

/// Tone mapping's two forms, as the device runs the per-pixel passes
/// (`DeviceInfo::pixel_passes`).
enum ToneMap {
    /// A fragment pass whose target is the 8-bit image's sRGB view: the attachment encodes
    /// sRGB, and on lavapipe a render target's write costs less than an `imageStore`.
    Fragment(RasterPipeline),
    /// A compute pass that encodes sRGB itself and stores to the image's UNORM view: a GPU's
    /// form (the H200 drew the fragment form's 1920x1080 in 0.31 ms, 4% of its bound).
    Compute(ComputePipeline),
}

/// The flat varyings (vec4 words) the fragment form needs for `shared_light_views`: the words
/// of a light and of each of its views, every light with as many views as the one with most
/// (raster/light_words.glsl).
fn light_varying_words(shared_light_views: &[(u32, u32)]) -> u32 {
    shared_light_views.len() as u32
        * (ids::LIGHTING_LIGHT_WORDS + ids::LIGHTING_VIEW_WORDS * most_views(shared_light_views))
}

/// The most shadow views one of the shared lights has (1 when there are none).
fn most_views(shared_light_views: &[(u32, u32)]) -> u32 {
    shared_light_views.iter().map(|v| v.1).max().unwrap_or(1)
}

/// What direct lighting's fragment form is specialised on (the scene's material terms and its
/// shared lights' views): a GI method that draws direct light with its own per-pixel light in
/// one pass (`GiMethod::record_lit_lookup`) builds its pipeline with these constants
/// ([`LitPipeline`]).
#[derive(Clone, Debug, PartialEq)]
struct DirectShape(Specialization);

impl DirectShape {
    /// Direct lighting's shape for `scene` lit by `raster_lights` on `gpu`, when it is a
    /// fragment pass (None: a compute pass, where `gpu` runs that form or the lights do not fit
    /// the flat varyings).
    fn of(gpu: &Gpu, scene: &Scene, raster_lights: &[Light]) -> Option<DirectShape> {
        let (shared_light_views, specialization) = lighting_specialization(scene, raster_lights);
        Self::fitting(gpu, &shared_light_views, specialization)
    }

    /// The shape of direct lighting specialised as `specialization` for `shared_light_views`,
    /// when `gpu` runs the fragment form (`DeviceInfo::pixel_passes`) and those fit its flat
    /// varyings.
    fn fitting(
        gpu: &Gpu,
        shared_light_views: &[(u32, u32)],
        specialization: Specialization,
    ) -> Option<DirectShape> {
        let fits = gpu.info.pixel_passes == PixelPasses::Fragment
            && !shared_light_views.is_empty()
            && light_varying_words(shared_light_views) <= ids::LIGHTING_VARYING_WORDS;
        fits.then_some(DirectShape(specialization))
    }
}

/// A GI method's pass that draws direct lighting with its own light in one pass
/// (`GiMethod::record_lit_lookup`): its pipeline, built for the shape direct lighting's fragment
/// form has in the scene the method was made for.
pub struct LitPipeline {
    shape: DirectShape,
    pipeline: RasterPipeline,
}

impl LitPipeline {
    /// The pass `name` for `scene` on `gpu`: the method's `shaders` (which include
    /// raster/lighting_vertex.glsl and raster/lighting_pixel.glsl) specialised with direct
    /// lighting's constants and what `own` adds, a full-screen triangle into the HDR image over
    /// the pixels a surface covers, replacing what was there. None where direct lighting is a
    /// compute pass there (the method then adds its light in a pass of its own).
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        name: &str,
        shaders: FullScreenShaders,
        own: impl FnOnce(Specialization) -> Specialization,
    ) -> GpuResult<Option<LitPipeline>> {
        let Some(shape) = DirectShape::of(gpu, scene, &scene.raster_lights()) else {
            return Ok(None);
        };
        let spec = own(shape.0.clone());
        let target = (HDR_FORMAT, Pixels::Covered);
        let pipeline = full_screen_with(gpu, name, shaders, target, Blend::Replace, &spec)?;
        Ok(Some(LitPipeline { shape, pipeline }))
    }

    /// Whether it draws `direct` (direct lighting of the shape it was built for).
    pub fn fits(&self, direct: &DirectDraw) -> bool {
        self.shape == *direct.shape
    }

    /// Draws the view's direct lighting `direct` with the method's light as pass `name`, the
    /// method's bindings `own` beside direct lighting's; the background keeps [`BACKGROUND`].
    /// False, with nothing recorded, where it does not fit `direct`.
    pub fn draw<'a, 'b>(
        &self,
        rec: &mut Recorder,
        direct: &DirectDraw<'a>,
        name: &'static str,
        own: impl IntoIterator<Item = Binding<'b>>,
    ) -> GpuResult<bool>
    where
        'a: 'b,
    {
        if !self.fits(direct) {
            return Ok(false);
        }
        let mut bindings: Vec<Binding<'b>> = direct.bindings.clone();
        bindings.extend(own);
        rec.raster(&RasterPass {
            name,
            pipeline: &self.pipeline,
            bindings: &bindings,
            push: &direct.push,
            color: &[(direct.hdr, 0, BACKGROUND)],
            depth: Some((direct.depth, 0)),
            draw: Draw::Vertices(3),
            keep_contents: false,
        })?;
        Ok(true)
    }
}

/// One view's direct lighting as a fragment pass, for a GI method to draw with its own light
/// (`GiMethod::record_lit_lookup`): the pipeline's shape, the bindings (the G-buffer, the
/// shadow map, the lights) and push constants of direct lighting, and the HDR image it writes.
pub struct DirectDraw<'a> {
    shape: &'a DirectShape,
    bindings: Vec<Binding<'a>>,
    push: LightingPush,
    hdr: &'a Image,
    /// The view's G-buffer depth: the pass shades only the pixels a surface covers
    /// (`Pixels::Covered`), and the rest keep their clear value, [`BACKGROUND`].
    depth: &'a Image,
}

/// What direct lighting leaves in the HDR image where no surface covers a pixel: no light
/// (the shaders' output there too), alpha 1.
pub const BACKGROUND: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

/// Direct lighting's shared lights' shadow views (empty when the scene has more lights than
/// [`MAX_SHARED_LIGHTS`]) and its specialisation constants for `scene` lit by `raster_lights`.
fn lighting_specialization(
    scene: &Scene,
    raster_lights: &[Light],
) -> (Vec<(u32, u32)>, Specialization) {
    let terms = MaterialTerms::of(scene);
    let shared_light_views = if raster_lights.len() <= MAX_SHARED_LIGHTS {
        shadow_view_ranges(raster_lights)
    } else {
        Vec::new()
    };
    let specialization = Specialization::new()
        .with_u32(0, u32::from(terms.emissive))
        .with_u32(1, u32::from(terms.glossy))
        .with_u32(2, shared_light_views.len() as u32)
        .with_u32(3, most_views(&shared_light_views));
    (shared_light_views, specialization)
}

/// The pipelines of the frame's own passes.
pub struct ScenePasses {
    /// The shared lights' shadow views (first, count), when direct lighting reads the lights at
    /// constant indices; empty when it loops over any number of them.
    shared_light_views: Vec<(u32, u32)>,
    shadow: RasterPipeline,
    /// The G-buffer writes emission and the glossy lobe (some material has one of them); else
    /// only position, normal and albedo, and the other two targets stay zero.
    gbuffer_terms: bool,
    gbuffer: RasterPipeline,
    lighting: DirectLighting,
    /// The fragment form's shape (None: the compute form).
    shape: Option<DirectShape>,
    tonemap: ToneMap,
}

impl ScenePasses {
    /// The frame's pipelines for `scene` lit by `raster_lights`: direct lighting leaves out
    /// emission or the glossy lobe when no material has it (lavapipe would run that code for
    /// every pixel), reads up to [`MAX_SHARED_LIGHTS`] lights at constant indices, and is a
    /// fragment pass where the device runs that form and those lights and their views fit its
    /// varyings (a compute pass otherwise). The lights may move
    /// later but not change in number or shadow views.
    pub fn new(gpu: &Gpu, scene: &Scene, raster_lights: &[Light]) -> GpuResult<ScenePasses> {
        let none = Specialization::new();
        let terms = MaterialTerms::of(scene);
        let (shared_light_views, lighting) = lighting_specialization(scene, raster_lights);
        let shape = DirectShape::fitting(gpu, &shared_light_views, lighting.clone());
        let gbuffer_terms = terms.emissive || terms.glossy;
        Ok(ScenePasses {
            lighting: direct_lighting(gpu, shape.is_some(), &lighting)?,
            shape,
            gbuffer_terms,
            shared_light_views,
            shadow: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: "shadow map",
                    vertex: shaders::RASTER_SHADOW_VERT,
                    fragment: None,
                    color_formats: &[],
                    depth: Some(Depth::Nearest(vk::Format::D32_SFLOAT)),
                    depth_bias: Some((1.25, 1.75)),
                    additive_blend: false,
                    conservative: false,
                    specialization: &none,
                },
            )?,
            gbuffer: RasterPipeline::new(
                gpu,
                &RasterPipelineDesc {
                    name: GBUFFER,
                    vertex: match gbuffer_terms {
                        true => shaders::RASTER_GBUFFER_VERT,
                        false => shaders::RASTER_GBUFFER_PLAIN_VERT,
                    },
                    fragment: Some(match gbuffer_terms {
                        true => shaders::RASTER_GBUFFER_FRAG,
                        false => shaders::RASTER_GBUFFER_PLAIN_FRAG,
                    }),
                    color_formats: &GBUFFER_FORMATS[..gbuffer_targets(gbuffer_terms)],
                    depth: Some(Depth::Nearest(GBUFFER_DEPTH_FORMAT)),
                    depth_bias: None,
                    additive_blend: false,
                    conservative: false,
                    specialization: &crate::scene::gpu::texture_specialization(scene),
                },
            )?,
            tonemap: tone_map(gpu)?,
        })
    }

    /// How direct lighting runs, for the profile.
    pub fn describe_direct_lighting(&self) -> String {
        let lights = self.shared_light_views.len();
        match self.lighting {
            DirectLighting::Fragment(_) => format!(
                "fragment pass, {lights} light(s) and their shadow views in {} of {} flat varyings",
                light_varying_words(&self.shared_light_views),
                ids::LIGHTING_VARYING_WORDS
            ),
            DirectLighting::Compute(_) if lights > 0 => {
                format!("compute pass, {lights} light(s) read at constant indices")
            }
            DirectLighting::Compute(_) => "compute pass, the lights read in a loop".into(),
        }
    }

    /// How tone mapping runs, for the profile.
    pub fn describe_tone_map(&self) -> String {
        match self.tonemap {
            ToneMap::Fragment(_) => {
                "fragment pass, rendering through the 8-bit image's sRGB view".into()
            }
            ToneMap::Compute(_) => {
                "compute pass, encoding sRGB and storing to the 8-bit image".into()
            }
        }
    }

    /// Shadow maps: one depth layer per shadow view.
    pub fn record_shadows(
        &self,
        rec: &mut Recorder,
        scene: &SceneBuffers,
        shadow_map: &Image,
    ) -> GpuResult<()> {
        for (layer, view_projection) in scene.shadow_view_matrices.iter().enumerate() {
            let push = ShadowPush {
                view_projection: view_projection.to_cols_array_2d(),
            };
            rec.raster(&RasterPass {
                name: "shadow map",
                pipeline: &self.shadow,
                bindings: &[
                    Binding::read(ids::RASTER_VERTICES, &scene.vertices),
                    Binding::read(ids::RASTER_TRIANGLES, &scene.triangles),
                ],
                push: &push,
                color: &[],
                depth: Some((shadow_map, layer as u32)),
                draw: Draw::Vertices(scene.vertex_count),
                keep_contents: false,
            })?;
        }
        Ok(())
    }

    /// A view's G-buffer from its eye.
    pub fn record_gbuffer(
        &self,
        rec: &mut Recorder,
        scene: &SceneBuffers,
        view: &View,
    ) -> GpuResult<()> {
        let push = GBufferPush {
            view_projection: view.eye.view_projection.to_cols_array_2d(),
            camera_position: view.eye.position.extend(1.0).to_array(),
        };
        let g = &view.gbuffer;
        rec.raster(&RasterPass {
            name: GBUFFER,
            pipeline: &self.gbuffer,
            bindings: &[
                Binding::read(ids::RASTER_VERTICES, &scene.vertices),
                Binding::read(ids::RASTER_TRIANGLES, &scene.triangles),
                Binding::read(ids::RASTER_MATERIALS, &scene.materials),
                Binding::read(ids::RASTER_TEXTURES, &scene.textures),
            ],
            push: &push,
            color: &[
                (&g.position, 0, [0.0; 4]),
                (&g.normal, 0, [0.0; 4]),
                (&g.albedo, 0, [0.0; 4]),
                (&g.emission, 0, [0.0; 4]),
                (&g.specular, 0, [0.0; 4]),
            ][..gbuffer_targets(self.gbuffer_terms)],
            depth: Some((&g.depth, 0)),
            draw: Draw::Vertices(scene.vertex_count),
            keep_contents: false,
        })
    }

    /// Direct light and emission (or, when `include_direct` is false, black) into a view's
    /// HDR image.
    pub fn record_direct_lighting(
        &self,
        rec: &mut Recorder,
        scene: &SceneBuffers,
        shadows: (&Image, &Sampler),
        view: &View,
        include_direct: bool,
    ) -> GpuResult<()> {
        let push = self.lighting_push(scene, view, include_direct);
        let mut bindings = lighting_inputs(scene, shadows, view);
        match &self.lighting {
            DirectLighting::Compute(pipeline) => {
                bindings.push(Binding::image_write(ids::LIGHTING_HDR_OUT, &view.hdr));
                rec.compute(&ComputePass {
                    name: DIRECT_LIGHTING,
                    pipeline,
                    bindings: &bindings,
                    push: &push,
                    threads: [view.width(), view.height(), 1],
                })
            }
            DirectLighting::Fragment(pipeline) => rec.raster(&RasterPass {
                name: DIRECT_LIGHTING,
                pipeline,
                bindings: &bindings,
                push: &push,
                color: &[(&view.hdr, 0, BACKGROUND)],
                depth: Some((&view.gbuffer.depth, 0)),
                draw: Draw::Vertices(3),
                keep_contents: false,
            }),
        }
    }

    /// A view's direct lighting for a GI method to draw with its own light, when direct
    /// lighting is a fragment pass (None: a compute pass).
    pub fn direct_draw<'a>(
        &'a self,
        scene: &'a SceneBuffers,
        shadows: (&'a Image, &'a Sampler),
        view: &'a View,
        include_direct: bool,
    ) -> Option<DirectDraw<'a>> {
        Some(DirectDraw {
            shape: self.shape.as_ref()?,
            bindings: lighting_inputs(scene, shadows, view),
            push: self.lighting_push(scene, view, include_direct),
            hdr: &view.hdr,
            depth: &view.gbuffer.depth,
        })
    }

    fn lighting_push(
        &self,
        scene: &SceneBuffers,
        view: &View,
        include_direct: bool,
    ) -> LightingPush {
        let mut push = LightingPush {
            camera_position: view.eye.position.extend(1.0).to_array(),
            size: [view.width(), view.height()],
            light_count: scene.light_count,
            include_direct: u32::from(include_direct),
            first_view: [0; MAX_SHARED_LIGHTS],
            view_count: [0; MAX_SHARED_LIGHTS],
        };
        for (i, &(first, count)) in self.shared_light_views.iter().enumerate() {
            push.first_view[i] = first;
            push.view_count[i] = count;
        }
        push
    }

    /// Exposure, tone mapping and sRGB encoding into a view's 8-bit output.
    pub fn record_tonemap(
        &self,
        rec: &mut Recorder,
        view: &View,
        exposure_ev: f32,
    ) -> GpuResult<()> {
        let push = TonemapPush {
            exposure_scale: exposure_ev.exp2(),
        };
        let hdr = Binding::image_read(ids::TONEMAP_HDR_IN, &view.hdr);
        match &self.tonemap {
            ToneMap::Fragment(pipeline) => rec.raster(&RasterPass {
                name: TONE_MAP,
                pipeline,
                bindings: &[hdr],
                push: &push,
                color: &[(&view.ldr, 0, [0.0; 4])],
                depth: None,
                draw: Draw::Vertices(3),
                keep_contents: false,
            }),
            ToneMap::Compute(pipeline) => rec.compute(&ComputePass {
                name: TONE_MAP,
                pipeline,
                bindings: &[hdr, Binding::image_write(ids::TONEMAP_LDR_OUT, &view.ldr)],
                push: &push,
                threads: [view.width(), view.height(), 1],
            }),
        }
    }
}

/// What direct lighting reads: a view's G-buffer, the shadow map and the lights.
fn lighting_inputs<'a>(
    scene: &'a SceneBuffers,
    shadows: (&'a Image, &'a Sampler),
    view: &'a View,
) -> Vec<Binding<'a>> {
    let g = &view.gbuffer;
    vec![
        Binding::image_read(ids::LIGHTING_GBUFFER_POSITION, &g.position),
        Binding::image_read(ids::LIGHTING_GBUFFER_NORMAL, &g.normal),
        Binding::image_read(ids::LIGHTING_GBUFFER_ALBEDO, &g.albedo),
        Binding::image_read(ids::LIGHTING_GBUFFER_EMISSION, &g.emission),
        Binding::image_read(ids::LIGHTING_GBUFFER_SPECULAR, &g.specular),
        Binding::sampled(ids::LIGHTING_SHADOW_MAP, shadows.0, shadows.1),
        Binding::read(ids::LIGHTING_LIGHTS, &scene.lights),
        Binding::read(ids::LIGHTING_SHADOW_VIEWS, &scene.shadow_views),
    ]
}

/// The G-buffer's targets: all five (`GBUFFER_FORMATS`) with emission and the glossy lobe, the
/// first three (position, normal, albedo) without.
fn gbuffer_targets(terms: bool) -> usize {
    if terms { GBUFFER_FORMATS.len() } else { 3 }
}

/// Tone mapping in the form `gpu` runs the per-pixel passes.
fn tone_map(gpu: &Gpu) -> GpuResult<ToneMap> {
    Ok(match gpu.info.pixel_passes {
        PixelPasses::Fragment => ToneMap::Fragment(full_screen(
            gpu,
            TONE_MAP,
            shaders::RASTER_TONEMAP_FRAG,
            (LDR_RENDER_FORMAT, Pixels::All),
            Blend::Replace,
            &Specialization::new(),
        )?),
        PixelPasses::Compute => ToneMap::Compute(ComputePipeline::new(
            gpu,
            TONE_MAP,
            shaders::RASTER_TONEMAP_COMP,
            &Specialization::new(),
        )?),
    })
}

/// Direct lighting's pipeline: the fragment form where the shared lights' varyings fit
/// (`fragment`), else the compute form.
fn direct_lighting(
    gpu: &Gpu,
    fragment: bool,
    specialization: &Specialization,
) -> GpuResult<DirectLighting> {
    if !fragment {
        return Ok(DirectLighting::Compute(ComputePipeline::new(
            gpu,
            DIRECT_LIGHTING,
            shaders::RASTER_LIGHTING_COMP,
            specialization,
        )?));
    }
    let shaders = FullScreenShaders {
        vertex: shaders::RASTER_LIGHTING_VERT,
        fragment: shaders::RASTER_LIGHTING_FRAG,
    };
    let target = (HDR_FORMAT, Pixels::Covered);
    Ok(DirectLighting::Fragment(full_screen_with(
        gpu,
        DIRECT_LIGHTING,
        shaders,
        target,
        Blend::Replace,
        specialization,
    )?))
}
