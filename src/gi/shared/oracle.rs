//! The path-traced image methods without a physical scale fit themselves to (the ambient
//! oracle, LightWave's gain): the scene's indirect light after one bounce, seen from its camera
//! at a small size, rendered again whenever the frame says the lights changed.

use crate::gpu::{Gpu, GpuResult};
use crate::imageio::HdrImage;
use crate::reference::{Bounces, PathTracer, ReferenceSettings};
use crate::scene::{Light, Scene};

/// Size of the image.
pub const SIZE: (u32, u32) = (64, 48);

pub struct IndirectOracle {
    /// The scene, its lights replaced by the frame's.
    pub scene: Scene,
    tracer: PathTracer,
    pub settings: ReferenceSettings,
}

impl IndirectOracle {
    pub fn new(gpu: &Gpu, scene: &Scene, spp: u32) -> anyhow::Result<IndirectOracle> {
        let (width, height) = SIZE;
        Ok(IndirectOracle {
            tracer: PathTracer::new(gpu, scene, width, height)?,
            scene: scene.clone(),
            settings: ReferenceSettings {
                width,
                height,
                spp,
                bounces: Bounces::Limited(1),
                seed: 1,
                strategy: Default::default(),
            },
        })
    }

    /// The indirect light of the scene as it is now.
    pub fn render(&mut self, gpu: &Gpu) -> anyhow::Result<HdrImage> {
        Ok(self.tracer.render(gpu, &self.settings, |_, _| {})?.indirect)
    }

    /// Take the frame's lights (the scene's own, as in `FrameContext::lights`).
    pub fn set_lights(&mut self, gpu: &Gpu, lights: &[Light]) -> GpuResult<()> {
        self.scene.lights = lights.to_vec();
        self.tracer.set_lights(gpu, &self.scene)
    }

    /// "a 64x48 path-traced image at N spp, one bounce".
    pub fn describe(&self) -> String {
        format!(
            "a {}x{} path-traced image at {} spp, one bounce",
            self.settings.width, self.settings.height, self.settings.spp
        )
    }
}
