//! Albedo textures on the rasteriser's side: the G-buffer samples a texture where the CPU's
//! rule (src/scene/texture.rs) says, at the surface point's texture coordinates. (The path
//! tracer's GPU = CPU check is in tests/reference.rs; every method's passes are checked with a
//! uniform texture in tests/conformance.rs.)

use glam::Vec2;

mod common;

#[test]
fn rasterised_direct_light_on_a_textured_plane_matches_the_cpu_texture_sampler() {
    let gpu = common::gpu();
    let scene = common::textured_plane_under_point_light(10.0);
    let (w, h) = (96, 72);
    let (_, raster) = common::render(&gpu, &scene, w, h);
    let light = scene.lights[0];
    let expected = |x: u32, y: u32| {
        let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let dir = scene.camera.ray_direction(pixel, w, h);
        let hit = scene
            .mesh
            .intersect(scene.camera.position, dir, 1e-4, 1e9)?;
        let p = scene.camera.position + dir * hit.t;
        let n = scene.mesh.face_normal(hit.triangle);
        let n = if n.dot(dir) > 0.0 { -n } else { n };
        let albedo = scene.albedo(hit.triangle, hit.uv);
        Some(albedo * light.irradiance_at(p, n) / std::f32::consts::PI)
    };
    let mut compared = 0;
    let mut worst = 0.0f32;
    for y in 0..h {
        for x in 0..w {
            let Some(e) = expected(x, y) else { continue };
            let r = raster[(y * w + x) as usize];
            for c in 0..3 {
                let error = (r[c] - e[c]).abs() / e.max_element().max(1e-3);
                worst = worst.max(error);
            }
            compared += 1;
        }
    }
    eprintln!("{compared} pixels, worst relative error {worst:.2e}");
    assert!(
        compared > (w * h / 2) as usize,
        "{compared} pixels compared"
    );
    assert!(worst < 5e-3, "worst relative error {worst}");
    common::assert_no_validation_errors(&gpu);
}
