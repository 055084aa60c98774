//! Helpers shared by the integration tests: a validated GPU and one-frame renders.
#![allow(dead_code)]

use vkgi::frame::{Frame, FrameOptions};
use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::scene::Scene;

/// A GPU context with the Khronos validation layers (synchronization validation included).
pub fn gpu() -> Gpu {
    Gpu::new(&GpuOptions {
        validation: true,
        device: None,
    })
    .expect("a Vulkan 1.3 device with validation layers (lavapipe in CI)")
}

/// Fail the test if the validation layers reported anything.
pub fn assert_no_validation_errors(gpu: &Gpu) {
    let errors = gpu.validation_errors();
    let first = gpu
        .validation_log()
        .map(|l| l.first_errors())
        .unwrap_or_default();
    assert_eq!(errors, 0, "validation errors: {first:#?}");
}

/// Render one raster frame of `scene` and return it with its linear HDR pixels.
pub fn render(gpu: &Gpu, scene: &Scene, width: u32, height: u32) -> (Frame, Vec<[f32; 3]>) {
    let frame = Frame::new(
        gpu,
        scene,
        FrameOptions {
            width,
            height,
            ..FrameOptions::default()
        },
    )
    .expect("frame");
    let mut ring = FrameRing::new(gpu, gpu.queues.graphics, 2).expect("frame ring");
    ring.submit_frame(gpu, &[], |rec| frame.record(rec))
        .expect("frame");
    ring.finish().expect("finish");
    let hdr = frame.read_hdr(gpu).expect("readback");
    (frame, hdr)
}

pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}
