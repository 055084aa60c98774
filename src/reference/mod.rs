//! The reference path tracer: the ground truth every GI method is scored against.
//!
//! A compute shader (shaders-glsl/reference/pathtrace.comp) traces the same scene, camera,
//! lights and Lambertian materials as the raster frame through an SAH BVH. Samples are summed in
//! f32 on the GPU for one batch at a time and added to f64 sums on the host, so long renders do
//! not drift. [`cpu`] is the same estimator on the CPU, used to check the GPU one.

pub mod cache;
pub mod cpu;

pub mod rng;

use ash::vk;
use glam::Mat4;
use gpu_allocator::MemoryLocation;

use crate::gpu::{Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult};
use crate::imageio::HdrImage;
use crate::scene::Scene;
use crate::scene::bvh::Bvh;
use crate::scene::gpu::{SceneBuffers, shadow_views};
use crate::shader_shared as ids;
use crate::shaders;

/// How many times a path may reflect before it ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum Bounces {
    /// At most `n + 1` reflections: 0 = direct light only, 1 = direct + one indirect bounce.
    Limited(u32),
    /// No limit: paths end by Russian roulette.
    #[serde(with = "unlimited_string")]
    Unlimited,
}

mod unlimited_string {
    pub fn serialize<S: serde::Serializer>(s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str("unlimited")
    }
    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
        let text = <String as serde::Deserialize>::deserialize(d)?;
        if text == "unlimited" {
            Ok(())
        } else {
            Err(serde::de::Error::custom("expected \"unlimited\""))
        }
    }
}

/// Largest finite bounce limit (paths are also capped at REFERENCE_MAX_DEPTH).
pub const MAX_BOUNCES: u32 = 1000;
/// Unlimited paths face Russian roulette from this bounce on.
pub const RUSSIAN_ROULETTE_START: u32 = 3;

impl Bounces {
    pub fn parse(text: &str) -> Result<Bounces, String> {
        match text {
            "inf" | "unlimited" | "infinite" => Ok(Bounces::Unlimited),
            _ => match text.parse::<u32>() {
                Ok(n) if n <= MAX_BOUNCES => Ok(Bounces::Limited(n)),
                _ => Err(format!(
                    "'{text}' is not a bounce count: use 0..={MAX_BOUNCES} or 'inf'"
                )),
            },
        }
    }

    fn shader_value(self) -> u32 {
        match self {
            Bounces::Limited(n) => n,
            Bounces::Unlimited => ids::REFERENCE_UNLIMITED_BOUNCES,
        }
    }
}

/// Where the path tracer runs. Both run the same estimator with the same random numbers
/// (tests/reference.rs holds them to each other).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Tracer {
    /// The CPU on every core when the Vulkan device is itself a CPU (lavapipe), else the device
    #[default]
    Auto,
    /// The compute shader on the Vulkan device
    Gpu,
    /// The CPU estimator (src/reference/cpu.rs) on every core
    Cpu,
}

impl Tracer {
    /// Whether this choice traces on the CPU when `gpu` is the Vulkan device.
    pub fn on_cpu(self, gpu: &Gpu) -> bool {
        match self {
            Tracer::Auto => gpu.info.is_cpu(),
            Tracer::Gpu => false,
            Tracer::Cpu => true,
        }
    }
}

/// Path-trace `scene` where `tracer` says; also returns where it ran, in words.
pub fn trace(
    gpu: &Gpu,
    scene: &Scene,
    settings: &ReferenceSettings,
    tracer: Tracer,
    progress: impl FnMut(u32, u32),
) -> anyhow::Result<(ReferenceImages, String)> {
    // The same limits on both paths, so a size is accepted or refused wherever it runs.
    crate::render::check_image_size(gpu, settings.width, settings.height)?;
    if tracer.on_cpu(gpu) {
        let threads = std::thread::available_parallelism().map_or(1, usize::from);
        let images = cpu::render(scene, settings, threads, progress)?;
        Ok((images, format!("the CPU ({threads} threads)")))
    } else {
        let mut tracer = PathTracer::new(gpu, scene, settings.width, settings.height)?;
        let images = tracer.render(gpu, settings, progress)?;
        Ok((images, gpu.info.name.clone()))
    }
}

/// Which strategies light surfaces from emissive triangles.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// Emitter sampling and BSDF-sampled hits, combined by the power heuristic.
    #[default]
    Mis,
    /// Emitter sampling (next-event estimation) alone.
    Light,
    /// Cosine-sampled bounces that hit emitters alone.
    Bsdf,
}

impl Strategy {
    fn shader_value(self) -> u32 {
        match self {
            Strategy::Mis => ids::REFERENCE_STRATEGY_MIS,
            Strategy::Light => ids::REFERENCE_STRATEGY_LIGHT,
            Strategy::Bsdf => ids::REFERENCE_STRATEGY_BSDF,
        }
    }
}

/// What to render.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub bounces: Bounces,
    pub seed: u32,
    /// How emissive surfaces are sampled (all three converge to the same image).
    #[serde(default)]
    pub strategy: Strategy,
}

/// The estimate, split into direct light (emission seen by the camera and light reflected once)
/// and indirect light (everything reflected more than once).
#[derive(Clone, Debug)]
pub struct ReferenceImages {
    pub direct: HdrImage,
    pub indirect: HdrImage,
}

impl ReferenceImages {
    pub fn combined(&self) -> HdrImage {
        let pixels = self
            .direct
            .pixels
            .iter()
            .zip(&self.indirect.pixels)
            .map(|(d, i)| [d[0] + i[0], d[1] + i[1], d[2] + i[2]])
            .collect();
        HdrImage::new(self.direct.width, self.direct.height, pixels)
    }
}

crate::push_constants! {
    struct PathTracePush {
        inverse_view_projection: [[f32; 4]; 4],
        camera_position_epsilon: [f32; 4],
        size: [u32; 2],
        first_sample: u32,
        samples: u32,
        seed: u32,
        max_bounces: u32,
        light_count: u32,
        rr_start: u32,
        has_emission: u32,
        emitter_count: u32,
        emitter_power: f32,
        strategy: u32,
    }
}

/// Samples per pixel summed in f32 on the GPU before the host adds them in f64.
pub const SAMPLES_PER_BATCH: u32 = 16;

/// Ray offset from surfaces, relative to the scene's diagonal.
pub fn ray_epsilon(scene: &Scene) -> f32 {
    1e-4 * (scene.bounds_max - scene.bounds_min).length().max(1e-6)
}

/// The camera's inverse view-projection, exactly as the raster frame builds the forward one.
pub fn inverse_view_projection(scene: &Scene, width: u32, height: u32) -> Mat4 {
    scene
        .camera
        .view_projection(
            width as f32 / height as f32,
            scene.bounds_min,
            scene.bounds_max,
        )
        .inverse()
}

/// Per-pixel sums of every sample so far, in f64 (f32 sums of 64k samples would drift).
struct HostSums {
    direct: Vec<[f64; 3]>,
    indirect: Vec<[f64; 3]>,
}

/// The GPU path tracer for one scene and image size.
pub struct PathTracer {
    pipeline: ComputePipeline,
    scene: SceneBuffers,
    bvh_nodes: Buffer,
    bvh_triangles: Buffer,
    emitters: Buffer,
    direct_sum: Buffer,
    indirect_sum: Buffer,
    direct_readback: Buffer,
    indirect_readback: Buffer,
    push: PathTracePush,
}

impl PathTracer {
    pub fn new(gpu: &Gpu, scene: &Scene, width: u32, height: u32) -> anyhow::Result<PathTracer> {
        crate::render::targets::check_image_size(gpu, width, height)?;
        let pipeline = ComputePipeline::new(
            gpu,
            "path trace",
            shaders::REFERENCE_PATHTRACE_COMP,
            &crate::scene::gpu::texture_specialization(scene),
        )?;
        let bvh = Bvh::build(&scene.mesh);
        let scene_buffers = SceneBuffers::upload(gpu, scene, &scene.lights, 16)?;
        let bvh_nodes = gpu.upload_storage("bvh nodes", bytemuck::cast_slice(&bvh.nodes))?;
        let bvh_triangles =
            gpu.upload_storage("bvh triangles", bytemuck::cast_slice(&bvh.gpu_triangles()))?;
        let bytes = u64::from(width) * u64::from(height) * 16;
        let sum = |name| gpu.create_buffer(&BufferDesc::storage(name, bytes));
        let readback = |name| {
            gpu.create_buffer(&BufferDesc {
                name,
                size: bytes,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
                texels: None,
            })
        };
        let camera = scene.camera.position;
        let found = crate::scene::emitters::Emitters::of(scene);
        let emitter_records: Vec<[u32; 2]> = found
            .triangles
            .iter()
            .zip(&found.cdf)
            .map(|(&t, &c)| [t, c.to_bits()])
            .collect();
        Ok(PathTracer {
            emitters: gpu.upload_storage("emitters", bytemuck::cast_slice(&emitter_records))?,
            pipeline,
            scene: scene_buffers,
            bvh_nodes,
            bvh_triangles,
            direct_sum: sum("direct sum")?,
            indirect_sum: sum("indirect sum")?,
            direct_readback: readback("direct readback")?,
            indirect_readback: readback("indirect readback")?,
            push: PathTracePush {
                inverse_view_projection: inverse_view_projection(scene, width, height)
                    .to_cols_array_2d(),
                camera_position_epsilon: [camera.x, camera.y, camera.z, ray_epsilon(scene)],
                size: [width, height],
                first_sample: 0,
                samples: 0,
                seed: 0,
                max_bounces: 0,
                light_count: scene.lights.len() as u32,
                rr_start: RUSSIAN_ROULETTE_START,
                has_emission: u32::from(
                    scene
                        .materials
                        .iter()
                        .any(|m| m.emission.max_element() > 0.0),
                ),
                emitter_count: found.triangles.len() as u32,
                emitter_power: found.power as f32,
                strategy: Strategy::default().shader_value(),
            },
        })
    }

    /// Take the scene's lights as they are now (moved, aimed or dimmed; the same number of
    /// lights as when the tracer was made).
    pub fn set_lights(&mut self, gpu: &Gpu, scene: &Scene) -> GpuResult<()> {
        let (lights, _) = shadow_views(scene, &scene.lights, 16);
        if lights.len() as u32 != self.push.light_count {
            return Err(crate::gpu::GpuError::Setup(format!(
                "the path tracer was built for {} lights, not {}",
                self.push.light_count,
                lights.len()
            )));
        }
        gpu.write_buffer(&self.scene.lights, bytemuck::cast_slice(&lights))
    }

    /// One batch: `samples` samples per pixel from `first_sample` on, summed in f32 on the GPU
    /// and added to the f64 sums.
    fn batch(
        &mut self,
        gpu: &Gpu,
        first_sample: u32,
        samples: u32,
        sums: &mut HostSums,
    ) -> GpuResult<()> {
        self.push.first_sample = first_sample;
        self.push.samples = samples;
        let push = self.push;
        gpu.one_shot(|rec| {
            rec.fill_buffers(
                "clear sums",
                &[(&self.direct_sum, 0), (&self.indirect_sum, 0)],
            );
            rec.compute(&ComputePass {
                name: "path trace",
                pipeline: &self.pipeline,
                bindings: &[
                    Binding::read(ids::REFERENCE_VERTICES, &self.scene.vertices),
                    Binding::read(ids::REFERENCE_TRIANGLES, &self.scene.triangles),
                    Binding::read(ids::REFERENCE_MATERIALS, &self.scene.materials),
                    Binding::read(ids::REFERENCE_LIGHTS, &self.scene.lights),
                    Binding::read(ids::REFERENCE_BVH_NODES, &self.bvh_nodes),
                    Binding::read(ids::REFERENCE_BVH_TRIANGLES, &self.bvh_triangles),
                    Binding::write(ids::REFERENCE_DIRECT_SUM, &self.direct_sum),
                    Binding::write(ids::REFERENCE_INDIRECT_SUM, &self.indirect_sum),
                    Binding::read(ids::REFERENCE_EMITTERS, &self.emitters),
                    Binding::read(ids::REFERENCE_TEXTURES, &self.scene.textures),
                ],
                push: &push,
                threads: [push.size[0], push.size[1], 1],
            })?;
            rec.copy_buffers(
                "read sums",
                &[
                    (
                        &self.direct_sum,
                        &self.direct_readback,
                        self.direct_sum.size,
                    ),
                    (
                        &self.indirect_sum,
                        &self.indirect_readback,
                        self.indirect_sum.size,
                    ),
                ],
            );
            rec.host_read(&self.direct_readback);
            rec.host_read(&self.indirect_readback);
            Ok(())
        })?;
        let add = |acc: &mut [[f64; 3]], b: &Buffer| -> GpuResult<()> {
            let batch: &[[f32; 4]] = bytemuck::cast_slice(b.mapped()?);
            for (a, v) in acc.iter_mut().zip(batch) {
                for c in 0..3 {
                    a[c] += f64::from(v[c]);
                }
            }
            Ok(())
        };
        add(&mut sums.direct, &self.direct_readback)?;
        add(&mut sums.indirect, &self.indirect_readback)
    }

    /// Render `settings.spp` samples per pixel; `progress(done, total)` after every batch.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        settings: &ReferenceSettings,
        mut progress: impl FnMut(u32, u32),
    ) -> anyhow::Result<ReferenceImages> {
        anyhow::ensure!(
            [settings.width, settings.height] == self.push.size,
            "the path tracer was built for another image size"
        );
        self.push.seed = settings.seed;
        self.push.strategy = settings.strategy.shader_value();
        self.push.max_bounces = settings.bounces.shader_value();
        let pixels = (settings.width * settings.height) as usize;
        let mut sums = HostSums {
            direct: vec![[0.0; 3]; pixels],
            indirect: vec![[0.0; 3]; pixels],
        };
        let mut done = 0;
        while done < settings.spp {
            let samples = SAMPLES_PER_BATCH.min(settings.spp - done);
            self.batch(gpu, done, samples, &mut sums)?;
            done += samples;
            progress(done, settings.spp);
        }
        Ok(ReferenceImages {
            direct: mean_image(sums.direct, settings)?,
            indirect: mean_image(sums.indirect, settings)?,
        })
    }
}

/// The image of per-pixel sums over `settings.spp` samples; non-finite radiance is an error.
pub(crate) fn mean_image(
    sums: impl IntoIterator<Item = [f64; 3]>,
    settings: &ReferenceSettings,
) -> anyhow::Result<HdrImage> {
    let n = f64::from(settings.spp.max(1));
    let pixels: Vec<[f32; 3]> = sums
        .into_iter()
        .map(|s| s.map(|v| (v / n) as f32))
        .collect();
    anyhow::ensure!(
        pixels.iter().flatten().all(|v| v.is_finite()),
        "the path tracer produced non-finite radiance"
    );
    Ok(HdrImage::new(settings.width, settings.height, pixels))
}
