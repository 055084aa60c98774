//! The timestamp profiler on lavapipe: one positive time per recorded pass, every frame read
//! back for 100 frames, and reading never blocks on a frame the GPU has not finished.

mod common;

use ash::vk;
use vkgi::gpu::frames::{FrameRing, SemaphoreWait, TimelineSemaphore};
use vkgi::gpu::{Binding, ComputePass, ComputePipeline, Specialization};
use vkgi::render::{Frame, FrameOptions};
use vkgi::scene::Scene;

const PASSES: [&str; 4] = ["shadow map", "g-buffer", "direct lighting", "tone map"];

fn small_frame(gpu: &vkgi::gpu::Gpu) -> Frame {
    let scene = Scene::load("cornell").unwrap();
    Frame::new(
        gpu,
        &scene,
        FrameOptions {
            width: 32,
            height: 24,
            shadow_map_size: 64,
            lights_move: true,
            ..FrameOptions::default()
        },
    )
    .unwrap()
}

#[test]
fn every_recorded_pass_gets_one_positive_time_per_frame() {
    let gpu = common::gpu();
    let mut frame = small_frame(&gpu);
    let mut ring = FrameRing::new(&gpu, 2).unwrap();
    for _ in 0..5 {
        ring.submit_frame(&gpu, &gpu.queues.graphics, &[], |rec| {
            frame.record(rec, None)
        })
        .unwrap();
    }
    ring.finish().unwrap();
    common::assert_no_validation_errors(&gpu);
    let report = ring.profiler.report();
    assert_eq!(report.frames, 5);
    let names: Vec<&str> = report.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, PASSES, "passes in recording order");
    for pass in &report.passes {
        assert_eq!(pass.samples, 5, "{}: one sample per frame", pass.name);
        assert_eq!(pass.per_frame_ns.len(), 5);
        assert!(
            pass.per_frame_ns.iter().all(|&t| t > 0.0),
            "{}: {:?}",
            pass.name,
            pass.per_frame_ns
        );
        assert!(pass.min_ns <= pass.median_ns && pass.median_ns <= pass.max_ns);
    }
    let frame_total = report.frame.as_ref().expect("a frame scope");
    let passes_sum: f64 = report.passes.iter().map(|p| p.avg_ns).sum();
    assert!(
        passes_sum <= frame_total.avg_ns * 1.001,
        "passes {passes_sum} > frame {}",
        frame_total.avg_ns
    );
    assert!(report.table().contains("direct lighting"));
    let trace = ring.profiler.chrome_trace();
    assert_eq!(
        trace["traceEvents"].as_array().unwrap().len(),
        5 * (PASSES.len() + 1)
    );
}

#[test]
fn reading_every_frame_for_100_frames_collects_them_all() {
    let gpu = common::gpu();
    let mut frame = small_frame(&gpu);
    let mut ring = FrameRing::new(&gpu, 2).unwrap();
    for n in 0..100u64 {
        ring.submit_frame(&gpu, &gpu.queues.graphics, &[], |rec| {
            frame.record(rec, None)
        })
        .unwrap();
        // Each submission reads the slot it reuses: all frames but the last two are in.
        assert_eq!(ring.profiler.frames_collected(), n.saturating_sub(1));
    }
    ring.finish().unwrap();
    common::assert_no_validation_errors(&gpu);
    let report = ring.profiler.report();
    assert_eq!(report.frames, 100);
    assert_eq!(report.dropped_scopes, 0);
    for pass in &report.passes {
        assert_eq!(pass.per_frame_ns.len(), 100, "{}", pass.name);
    }
}

#[test]
fn collecting_an_unfinished_frame_returns_at_once_instead_of_waiting() {
    let gpu = common::gpu();
    let mut frame = small_frame(&gpu);
    let mut ring = FrameRing::new(&gpu, 2).unwrap();
    // The GPU cannot start this frame until the host signals the semaphore.
    let gate = TimelineSemaphore::new(&gpu, 0).unwrap();
    let wait = SemaphoreWait {
        semaphore: gate.raw,
        value: 1,
        stage: vk::PipelineStageFlags2::ALL_COMMANDS,
    };
    ring.submit_frame(&gpu, &gpu.queues.graphics, &[wait], |rec| {
        frame.record(rec, None)
    })
    .unwrap();
    let (slot, fence) = ring.last_submitted().unwrap();
    for _ in 0..3 {
        assert!(
            !ring.profiler.collect_if_ready(slot, fence).unwrap(),
            "the frame cannot have run yet"
        );
    }
    assert_eq!(ring.profiler.frames_collected(), 0);
    gate.signal(1).unwrap();
    ring.finish().unwrap();
    assert_eq!(ring.profiler.frames_collected(), 1);
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_pass_whose_bindings_disagree_with_its_shader_fails_naming_the_pass() {
    let gpu = common::gpu();
    let frame = small_frame(&gpu);
    let pipeline = ComputePipeline::new(
        &gpu,
        "anaglyph",
        vkgi::shaders::VIEW_ANAGLYPH_COMP,
        &Specialization::new(),
    )
    .unwrap();
    let result = gpu.one_shot(|rec| {
        rec.compute(&ComputePass {
            name: "mis-bound anaglyph",
            pipeline: &pipeline,
            // Binding 1 (the right eye) is missing, and the push constants are absent.
            bindings: &[Binding::image_read(
                vkgi::shader_shared::ANAGLYPH_LEFT,
                &frame.view().ldr,
            )],
            push: &(),
            threads: [32, 24, 1],
        })
    });
    let message = result.unwrap_err().to_string();
    assert!(
        message.contains("mis-bound anaglyph") && message.contains("binding 1"),
        "{message}"
    );
    common::assert_no_validation_errors(&gpu);
}

vkgi::push_constants! {
    /// The anaglyph's 24 bytes of push constants, but as six members instead of three.
    struct MislaidAnaglyphPush {
        origin_x: i32,
        origin_y: i32,
        tile_x: i32,
        tile_y: i32,
        size_x: i32,
        size_y: i32,
    }
}

#[test]
fn push_constant_layouts_and_write_intent_are_checked_against_the_shader() {
    let gpu = common::gpu();
    let frame = small_frame(&gpu);
    let pipeline = ComputePipeline::new(
        &gpu,
        "anaglyph",
        vkgi::shaders::VIEW_ANAGLYPH_COMP,
        &Specialization::new(),
    )
    .unwrap();
    let view = frame.view();
    let mislaid = MislaidAnaglyphPush {
        origin_x: 0,
        origin_y: 0,
        tile_x: 32,
        tile_y: 24,
        size_x: 32,
        size_y: 24,
    };
    let record = |name: &'static str, target: Binding| {
        use vkgi::shader_shared::{ANAGLYPH_LEFT, ANAGLYPH_RIGHT};
        gpu.one_shot(|rec| {
            rec.compute(&ComputePass {
                name,
                pipeline: &pipeline,
                bindings: &[
                    Binding::image_read(ANAGLYPH_LEFT, &view.ldr),
                    Binding::image_read(ANAGLYPH_RIGHT, &view.ldr),
                    target,
                ],
                push: &mislaid,
                threads: [32, 24, 1],
            })
        })
    };
    let target = vkgi::shader_shared::ANAGLYPH_TARGET;
    let message = record(
        "mislaid push constants",
        Binding::image_write(target, &view.ldr),
    )
    .unwrap_err()
    .to_string();
    assert!(
        message.contains("mislaid push constants") && message.contains("6 members in Rust but 3"),
        "{message}"
    );
    // The output image is written by the shader but declared read: the barrier would be wrong.
    let message = record(
        "read-declared output",
        Binding::image_read(target, &view.ldr),
    )
    .unwrap_err()
    .to_string();
    assert!(
        message.contains("binding 2 is declared read, but the shader may write it"),
        "{message}"
    );
    common::assert_no_validation_errors(&gpu);
}

vkgi::push_constants! {
    /// The bandwidth probes' push constants.
    struct CopyPush {
        count: u32,
    }
}

#[test]
fn a_buffer_is_read_as_texels_only_through_its_texel_view() {
    use vkgi::gpu::BufferDesc;
    use vkgi::shader_shared::{LIMITS_DESTINATION, LIMITS_SOURCE};
    let gpu = common::gpu();
    let pipeline = ComputePipeline::new(
        &gpu,
        "texel copy",
        vkgi::shaders::LIMITS_COPY_TEXELS_COMP,
        &Specialization::new(),
    )
    .unwrap();
    let count = 100u32;
    let values: Vec<[f32; 4]> = (0..count)
        .map(|i| {
            [
                i as f32,
                -0.5 * i as f32,
                1e-3 * i as f32,
                f32::MAX / (i + 1) as f32,
            ]
        })
        .collect();
    let bytes = u64::from(count) * 16;
    let with_view = gpu
        .create_buffer(&BufferDesc::storage_texels("texel source", bytes))
        .unwrap();
    let without_view = gpu
        .create_buffer(&BufferDesc::storage("plain source", bytes))
        .unwrap();
    let destination = gpu
        .create_buffer(&BufferDesc::storage("copy destination", bytes))
        .unwrap();
    gpu.write_buffer(&with_view, bytemuck::cast_slice(&values))
        .unwrap();
    let copy = |source| {
        gpu.one_shot(|rec| {
            rec.compute(&ComputePass {
                name: "texel copy",
                pipeline: &pipeline,
                bindings: &[
                    Binding::texels(LIMITS_SOURCE, source),
                    Binding::write(LIMITS_DESTINATION, &destination),
                ],
                push: &CopyPush { count },
                threads: [count, 1, 1],
            })
        })
    };
    let message = copy(&without_view).unwrap_err().to_string();
    assert!(
        message.contains(
            "reads buffer 'plain source' as texels, but it was made without a texel view"
        ),
        "{message}"
    );
    copy(&with_view).unwrap();
    let copied: Vec<[f32; 4]> =
        bytemuck::cast_slice(&gpu.read_buffer(&destination).unwrap()).to_vec();
    assert_eq!(copied, values, "a texel fetch reads the buffer's own bits");
    common::assert_no_validation_errors(&gpu);
}

/// A frame whose lights and geometry did not change keeps its shadow maps: drawn in the first
/// frame and again after the lights are set, with the same image as frames that draw them
/// every time (`lights_move`), which the profile and the benches measure.
#[test]
fn a_frame_whose_lights_stayed_keeps_its_shadow_maps() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let run = |lights_move: bool| {
        let mut frame = Frame::new(
            &gpu,
            &scene,
            FrameOptions {
                width: 32,
                height: 24,
                shadow_map_size: 64,
                lights_move,
                ..FrameOptions::default()
            },
        )
        .unwrap();
        let mut ring = FrameRing::new(&gpu, 2).unwrap();
        for f in 0..4 {
            if f == 2 {
                frame.set_lights(&scene);
            }
            ring.submit_frame(&gpu, &gpu.queues.graphics, &[], |rec| {
                frame.record(rec, None)
            })
            .unwrap();
        }
        ring.finish().unwrap();
        let report = ring.profiler.report();
        let shadow_frames = report
            .passes
            .iter()
            .find(|p| p.name == "shadow map")
            .map_or(0, |p| p.per_frame_ns.len());
        (frame.read_hdr(&gpu).unwrap(), shadow_frames)
    };
    let (kept, kept_frames) = run(false);
    let (drawn, drawn_frames) = run(true);
    common::assert_no_validation_errors(&gpu);
    assert_eq!(
        (kept_frames, drawn_frames),
        (2, 4),
        "frames that drew shadow maps"
    );
    assert!(kept.iter().flatten().any(|&v| v > 0.0), "no light");
    assert_eq!(kept, drawn, "the kept shadow maps changed the image");
}
