//! The invariants every registered GI method must keep, checked over the registry: a method
//! added to src/gi/mod.rs gets these tests without writing them. Each runs headless at a small
//! size on lavapipe with the validation layers on, with the method at its default settings and
//! for as many frames as it declares it needs to settle.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use vkgi::gi::registry::{self, MethodEntry, Setup};
use vkgi::gi::{FrameContext, GiMethod};
use vkgi::gpu::frames::FrameRing;
use vkgi::gpu::{Buffer, BufferDesc, Gpu, GpuResult, Image, ImageDesc, Recorder, Stage};
use vkgi::render::runner::run_frames;
use vkgi::render::{Eye, Frame, FrameOptions, SubmitPlan};
use vkgi::scene::texture::{linear_to_srgb, srgb_to_linear};
use vkgi::scene::{Scene, Texture};
use vkgi::view::cave::Cave;

mod common;

const SIZE: (u32, u32) = (32, 24);

fn options(indirect_only: bool) -> FrameOptions {
    FrameOptions {
        width: SIZE.0,
        height: SIZE.1,
        shadow_map_size: 256,
        indirect_only,
        ..FrameOptions::default()
    }
}

fn build(gpu: &Gpu, scene: &Scene, entry: &MethodEntry) -> Box<dyn GiMethod> {
    let settings = entry
        .settings(&[])
        .unwrap_or_else(|e| panic!("{}: {e}", entry.name));
    let method = entry
        .create(&Setup::new(gpu, scene), &settings)
        .unwrap_or_else(|e| panic!("{}: {e:#}", entry.name));
    assert_eq!(method.name(), entry.name, "registered name");
    method
}

fn settle_frames(entry: &MethodEntry) -> u32 {
    let settings = entry.settings(&[]).expect("default settings");
    (entry.settle_frames)(&settings)
}

/// The first view's HDR pixels after the method's settle frames (or none for `None`).
fn render(
    gpu: &Gpu,
    scene: &Scene,
    entry: Option<&MethodEntry>,
    indirect_only: bool,
) -> Vec<[f32; 3]> {
    let mut frame = Frame::new(gpu, scene, options(indirect_only)).expect("frame");
    match entry {
        Some(entry) => {
            let mut method = build(gpu, scene, entry);
            run_frames(
                gpu,
                &mut frame,
                Some(method.as_mut()),
                0,
                settle_frames(entry),
            )
            .expect("frames");
        }
        None => {
            run_frames(gpu, &mut frame, None, 0, 1).expect("frame");
        }
    }
    frame.read_hdr(gpu).expect("readback")
}

fn with_flux(scene: &Scene, scale: f32) -> Scene {
    let mut scaled = scene.clone();
    for light in &mut scaled.lights {
        light.flux *= scale;
    }
    scaled
}

fn max_abs(pixels: &[[f32; 3]]) -> f32 {
    pixels.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()))
}

fn mean_abs_difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| f64::from((p[c] - q[c]).abs())))
        .sum();
    sum / (3 * a.len()) as f64
}

/// Every built-in scene (the atrium at a small detail: its default, 225 000 triangles, is for
/// benches and reports).
const SCENES: &[&str] = &[
    "cornell",
    "two-rooms",
    "cornell-area",
    "cornell-area-closed",
    "cornell-area-16",
    "four-boxes",
    "four-boxes-4",
    "lightwave-boxes",
    "atrium:1",
    "cornell-glossy",
];

#[test]
fn every_method_renders_every_built_in_scene_finite_and_lit() {
    let gpu = common::gpu();
    for &scene_name in SCENES {
        let scene = Scene::load(scene_name).unwrap();
        for entry in registry::methods() {
            let image = render(&gpu, &scene, Some(entry), true);
            assert!(
                image.iter().flatten().all(|v| v.is_finite()),
                "{} on {scene_name}: non-finite indirect light",
                entry.name
            );
            assert!(
                max_abs(&image) > 0.0,
                "{} on {scene_name}: no indirect light at all",
                entry.name
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn zero_flux_gives_exactly_zero_and_indirect_light_is_linear_in_flux() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    for entry in registry::methods() {
        let dark = render(&gpu, &with_flux(&scene, 0.0), Some(entry), true);
        assert!(
            dark.iter().flatten().all(|&v| v == 0.0),
            "{}: zero flux left {} as the brightest indirect value",
            entry.name,
            max_abs(&dark)
        );
        let unit = render(&gpu, &scene, Some(entry), true);
        let brightest = max_abs(&unit);
        assert!(brightest > 0.0, "{}: no indirect light", entry.name);
        for scale in [1e-6f32, 1e6] {
            let scaled = render(&gpu, &with_flux(&scene, scale), Some(entry), true);
            let worst = scaled
                .iter()
                .zip(&unit)
                .flat_map(|(s, u)| (0..3).map(move |c| (s[c] / scale - u[c]).abs()))
                .fold(0.0f32, f32::max);
            assert!(
                worst <= 1e-4 * brightest,
                "{}: flux × {scale:e} is not linear: off by {worst:e} of {brightest:e}",
                entry.name
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// `scene` with every material's albedo moved into a one-texel texture (factor 1), and the
/// untextured twin whose albedo is what that texel decodes to.
fn uniformly_textured(scene: &Scene) -> (Scene, Scene) {
    let mut textured = scene.clone();
    let mut plain = scene.clone();
    for (t, p) in textured.materials.iter_mut().zip(&mut plain.materials) {
        let encoded = t
            .albedo
            .to_array()
            .map(|c| (linear_to_srgb(c) * 255.0).round() as u32);
        let texel = encoded[0] | encoded[1] << 8 | encoded[2] << 16 | 0xff << 24;
        let texture = Texture::new("uniform", 1, 1, vec![texel]).unwrap();
        p.albedo = Vec3::from(encoded.map(|e| srgb_to_linear(e as f32 / 255.0)));
        t.albedo = Vec3::ONE;
        t.albedo_texture = Some(Arc::new(texture));
    }
    (textured, plain)
}

#[test]
fn textured_albedo_reaches_every_pass_of_every_method() {
    let gpu = common::gpu();
    let (textured, plain) = uniformly_textured(&Scene::load("cornell").unwrap());
    for entry in std::iter::once(None).chain(registry::methods().map(Some)) {
        let name = entry.map_or("direct light", |e| e.name);
        let a = render(&gpu, &textured, entry, false);
        let b = render(&gpu, &plain, entry, false);
        let (worst, peak) = common::worst_difference(&a, &b);
        assert!(
            worst <= 1e-4 * peak,
            "{name}: a uniform texture renders {worst} away from its plain albedo (peak {peak})"
        );
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn indirect_only_images_hold_no_direct_light() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let direct = render(&gpu, &scene, None, false);
    for entry in registry::methods() {
        let full = render(&gpu, &scene, Some(entry), false);
        let indirect = render(&gpu, &scene, Some(entry), true);
        let brightest = max_abs(&full);
        let worst = full
            .iter()
            .zip(&direct)
            .zip(&indirect)
            .flat_map(|((f, d), i)| (0..3).map(move |c| (f[c] - d[c] - i[c]).abs()))
            .fold(0.0f32, f32::max);
        assert!(
            worst <= 1e-4 * brightest,
            "{}: indirect-only differs from full minus direct by {worst:e} of {brightest:e}",
            entry.name
        );
    }
    common::assert_no_validation_errors(&gpu);
}

/// After moving `what` and `frames` frames, the image is within 5% of the change the move made
/// (`before` the move, `after` the frames, and `fresh`: the moved scene rendered anew).
fn assert_followed(
    entry: &MethodEntry,
    what: &str,
    frames: impl std::fmt::Display,
    images: [&[[f32; 3]]; 3],
) {
    let [before, after, fresh] = images;
    let change = mean_abs_difference(before, fresh);
    let lag = mean_abs_difference(after, fresh);
    assert!(
        change > 0.0,
        "{}: moving {what} changed nothing",
        entry.name
    );
    assert!(
        lag <= 0.05 * change,
        "{}: {frames} frames after moving {what}, {lag:e} from the settled image (the move changed it by {change:e})",
        entry.name
    );
}

#[test]
fn a_moved_light_is_followed_within_the_declared_settle_frames() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let extent = (scene.bounds_max - scene.bounds_min).length();
    let mut moved = scene.clone();
    moved.lights[0].position += Vec3::new(0.15 * extent, 0.0, 0.05 * extent);
    for entry in registry::methods() {
        let frames = settle_frames(entry);
        let fresh = render(&gpu, &moved, Some(entry), true);
        let mut frame = Frame::new(&gpu, &scene, options(true)).unwrap();
        let mut method = build(&gpu, &scene, entry);
        run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames).unwrap();
        let before = frame.read_hdr(&gpu).unwrap();
        frame.set_lights(&moved);
        run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames).unwrap();
        let after = frame.read_hdr(&gpu).unwrap();
        assert_followed(entry, "the light", frames, [&before, &after, &fresh]);
    }
    common::assert_no_validation_errors(&gpu);
}

#[test]
fn a_moved_object_is_followed_within_the_declared_settle_frames() {
    let gpu = common::gpu();
    // The Cornell box's tall block (its last 10 triangles) jumps 0.12 m toward the red wall
    // once the method has settled.
    let scene = Scene::load("cornell").unwrap();
    let n = scene.mesh.triangle_count();
    let block: Vec<usize> = (n - 10..n).collect();
    let step = Vec3::new(0.12, 0.0, -0.06);
    for entry in registry::methods() {
        let frames = u64::from(settle_frames(entry));
        let keys = vec![(frames - 1, Vec3::ZERO), (frames, step)];
        let path = vkgi::scene::dynamic::Path::new(keys, false).unwrap();
        let mut moving = scene.clone();
        moving.add_dynamic("tall", &block, path).unwrap();
        let mut frame = Frame::new(&gpu, &moving, options(true)).unwrap();
        let mut method = build(&gpu, &moving, entry);
        run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames as u32).unwrap();
        let before = frame.read_hdr(&gpu).unwrap();
        let rebuild = |s: &Scene| Ok(build(&gpu, s, entry));
        let mut at_end = moving.clone();
        at_end.pose(2 * frames - 1);
        let fresh = render(&gpu, &at_end, Some(entry), true);
        // Frames `frames`..2 frames of the animation: the block moves in the first.
        for index in frames..2 * frames {
            let moved = moving.pose(index);
            let mut ring = FrameRing::new(&gpu, 2).unwrap();
            vkgi::render::runner::follow(
                &gpu,
                &mut ring,
                &mut frame,
                &moving,
                &moved,
                Some(&mut method),
                &rebuild,
            )
            .unwrap();
            frame
                .submit(&gpu, &mut ring, Some(method.as_mut()))
                .unwrap();
            ring.finish().unwrap();
        }
        let after = frame.read_hdr(&gpu).unwrap();
        assert_followed(entry, "the block", frames, [&before, &after, &fresh]);
    }
    common::assert_no_validation_errors(&gpu);
}

/// Runs of each (stage, pass) of `method` per frame.
fn runs_per_frame(ring: &FrameRing, method: &str) -> HashMap<(Stage, &'static str), f64> {
    let samples = ring.profiler.samples();
    let frames = samples
        .iter()
        .map(|s| s.frame)
        .collect::<std::collections::HashSet<_>>()
        .len()
        .max(1) as f64;
    let mut runs = HashMap::new();
    for s in samples.iter().filter(|s| s.tag.method == Some(method)) {
        *runs.entry((s.tag.stage, s.tag.pass)).or_insert(0.0) += 1.0 / frames;
    }
    runs
}

#[test]
fn the_profile_names_every_method_pass_and_the_cave_shares_its_light() {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let cave = Cave::placed(&scene, 0.2, Vec3::new(0.2, 0.1, 0.3));
    let walls: Vec<Eye> = cave.eyes(&scene);
    for entry in registry::methods() {
        let frames = settle_frames(entry).max(2);
        let single = {
            let mut frame = Frame::new(&gpu, &scene, options(true)).unwrap();
            let mut method = build(&gpu, &scene, entry);
            run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames).unwrap()
        };
        let four = {
            let mut frame = Frame::with_eyes(&gpu, &scene, options(true), &walls).unwrap();
            let mut method = build(&gpu, &scene, entry);
            run_frames(&gpu, &mut frame, Some(method.as_mut()), 0, frames).unwrap()
        };
        for s in single.profiler.samples() {
            let gi = matches!(
                s.tag.stage,
                Stage::GiView | Stage::GiLight | Stage::GiPart | Stage::GiLookup
            );
            assert_eq!(
                gi,
                s.tag.method == Some(entry.name),
                "{}: pass '{}' in stage {:?} is tagged {:?}",
                entry.name,
                s.name,
                s.tag.stage,
                s.tag.method
            );
        }
        let (one, cave) = (
            runs_per_frame(&single, entry.name),
            runs_per_frame(&four, entry.name),
        );
        assert!(
            !one.is_empty(),
            "{}: no pass tagged with the method",
            entry.name
        );
        for (&(stage, pass), &n) in &one {
            let expected = match stage {
                Stage::GiView | Stage::GiLookup => 4.0 * n,
                _ => n,
            };
            let got = cave.get(&(stage, pass)).copied().unwrap_or(0.0);
            assert!(
                (got - expected).abs() < 1e-9,
                "{}: '{pass}' ({stage:?}) runs {got} times per CAVE frame, {n} with one view",
                entry.name
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}

/// What the two parts of a `SharingParts` share.
enum Shared {
    /// Both clear one buffer.
    WrittenBuffer(Buffer),
    /// Both copy one image out, each into its own buffer: the first moves the image to the
    /// copy's layout, which rewrites it under the second's read.
    RelaidImage(Box<(Image, [Buffer; 2])>),
}

/// A method whose two parts share a resource that one of them writes: run at once on two
/// queues, nothing would order them.
struct SharingParts {
    shared: Shared,
}

impl GiMethod for SharingParts {
    fn name(&self) -> &'static str {
        "sharing-parts"
    }

    fn record_light(&mut self, _: &mut Recorder, _: &FrameContext) -> GpuResult<()> {
        Ok(())
    }

    fn parts(&self) -> &'static [&'static str] {
        &["first", "second"]
    }

    fn record_part(&mut self, rec: &mut Recorder, _: &FrameContext, part: usize) -> GpuResult<()> {
        match &self.shared {
            Shared::WrittenBuffer(buffer) => rec.fill_buffer("clear", buffer, 0),
            Shared::RelaidImage(shared) => {
                let (image, copies) = &**shared;
                rec.copy_image_to_buffer("copy out", image, &copies[part])
            }
        }
        Ok(())
    }

    fn record_lookup(&self, _: &mut Recorder, _: &FrameContext, _: usize) -> GpuResult<()> {
        Ok(())
    }

    fn describe(&self) -> Vec<String> {
        Vec::new()
    }
}

/// The error of the first frame run with `shared` between two parts, recorded into one command
/// buffer (`Sequential`) or submitted part by part (`Async`: on lavapipe's one queue the
/// submissions run in turn), with no validation error on the way.
fn sharing_error(submit: SubmitPlan, shared: impl FnOnce(&Gpu) -> Shared) -> String {
    let gpu = common::gpu();
    let scene = Scene::load("cornell").unwrap();
    let options = FrameOptions {
        submit,
        ..options(false)
    };
    let mut frame = Frame::new(&gpu, &scene, options).unwrap();
    let mut method = SharingParts {
        shared: shared(&gpu),
    };
    let error = match run_frames(&gpu, &mut frame, Some(&mut method), 0, 1) {
        Ok(_) => panic!("the frame ran"),
        Err(error) => error.to_string(),
    };
    drop(method);
    drop(frame);
    common::assert_no_validation_errors(&gpu);
    error
}

#[test]
fn parts_that_share_what_one_writes_fail_the_frame_naming_it() {
    for submit in [SubmitPlan::Sequential, SubmitPlan::Async] {
        let written = sharing_error(submit, |gpu| {
            let desc = BufferDesc::storage("the shared buffer", 256);
            Shared::WrittenBuffer(gpu.create_buffer(&desc).unwrap())
        });
        assert_eq!(
            written,
            "the method's parts first and second both use the shared buffer and one of them \
             writes it or changes its layout: parts may run at once on different queues, so they \
             must not share what either writes (a shared image's layout is best set before the \
             parts, in the method's light work)",
            "{submit:?}"
        );
        let relaid = sharing_error(submit, |gpu| {
            let usage = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::SAMPLED;
            let desc =
                ImageDesc::new_2d("the shared image", vk::Format::R8G8B8A8_UNORM, 4, 4, usage);
            let copy = |name| gpu.create_buffer(&BufferDesc::storage(name, 64)).unwrap();
            let image = gpu.create_image(&desc).unwrap();
            Shared::RelaidImage(Box::new((image, [copy("copy 0"), copy("copy 1")])))
        });
        assert!(
            relaid.contains("parts first and second both use the shared image"),
            "{submit:?}: {relaid}"
        );
    }
}

/// The methods that draw their light inside direct lighting's fragment pass
/// (`GiMethod::record_lit_lookup`); the others add it in passes of their own after it.
const DRAWN_INSIDE_DIRECT_LIGHTING: &[&str] = &["ambient", "ilpv", "lpv", "radiosity"];

/// A method drawn inside direct lighting gives the image of direct lighting followed by its
/// passes apart (`FrameOptions::lookup_apart`), with direct light and with indirect light alone,
/// in the glossy Cornell box (every material term on): within 1e-6 of the brightest pixel. The
/// profile names the pass that drew it ("direct lighting + ...") where and only where it was.
#[test]
fn every_method_drawn_inside_direct_lighting_gives_the_image_of_its_passes_apart() {
    let gpu = common::gpu_with(Some(vkgi::gpu::PixelPasses::Fragment));
    let scene = Scene::load("cornell-glossy").unwrap();
    for entry in registry::methods() {
        for indirect_only in [false, true] {
            let run = |lookup_apart: bool| {
                let options = FrameOptions {
                    lookup_apart,
                    ..options(indirect_only)
                };
                let mut frame = Frame::new(&gpu, &scene, options).unwrap();
                let mut method = build(&gpu, &scene, entry);
                let passes = common::run_naming_passes(&gpu, &mut frame, method.as_mut(), 2);
                (frame.read_hdr(&gpu).unwrap(), passes)
            };
            let (inside, inside_passes) = run(false);
            let (apart, apart_passes) = run(true);
            let case = format!("{}, indirect only {indirect_only}", entry.name);
            let drawn_inside =
                |passes: &[String]| passes.iter().any(|p| p.starts_with("direct lighting + "));
            let direct_apart = |passes: &[String]| passes.iter().any(|p| p == "direct lighting");
            assert_eq!(
                drawn_inside(&inside_passes),
                DRAWN_INSIDE_DIRECT_LIGHTING.contains(&entry.name),
                "{case}: {inside_passes:?}"
            );
            assert_eq!(
                direct_apart(&inside_passes),
                !drawn_inside(&inside_passes),
                "{case}: {inside_passes:?}"
            );
            assert!(
                direct_apart(&apart_passes) && !drawn_inside(&apart_passes),
                "{case}: {apart_passes:?}"
            );
            assert!(max_abs(&inside) > 0.0, "{case}: black");
            let (worst, brightest) = common::worst_difference(&inside, &apart);
            assert!(
                worst <= 1e-6 * brightest,
                "{case}: inside and apart differ by {worst} (brightest {brightest})"
            );
        }
    }
    common::assert_no_validation_errors(&gpu);
}
