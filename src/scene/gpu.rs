//! The scene in GPU buffers, in the layouts the shaders declare (shaders-glsl/common/scene.glsl
//! and lights.glsl): vertices, per-triangle materials, materials, lights, shadow views.

use bytemuck::{Pod, Zeroable};
use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, Vec3};

use super::{Light, LightKind, Mesh, Scene};
use crate::gpu::{Buffer, Gpu, GpuResult, Specialization};
use crate::shader_shared::{
    LIGHT_KIND_COSINE, LIGHT_KIND_POINT, LIGHT_KIND_SPOT, SPEC_SCENE_TEXTURED,
};

/// The specialisation of a shader that includes common/texture.glsl for `scene`: without any
/// albedo texture, the texture code is compiled out.
pub fn texture_specialization(scene: &Scene) -> Specialization {
    Specialization::new().with_u32(SPEC_SCENE_TEXTURED, u32::from(scene.textured()))
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuVertex {
    /// xyz, w = texture coordinate u.
    pub position: [f32; 4],
    /// xyz shading normal (zero: flat), w = texture coordinate v.
    pub normal: [f32; 4],
}

impl GpuVertex {
    /// Vertex `i` of `mesh`.
    pub fn of(mesh: &Mesh, i: usize) -> GpuVertex {
        GpuVertex {
            position: mesh.positions[i].extend(mesh.texcoords[i].x).to_array(),
            normal: mesh.normals[i].extend(mesh.texcoords[i].y).to_array(),
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuMaterial {
    /// rgb albedo (factor), w = 1 + index of its albedo texture, or 0 for none.
    pub albedo: [f32; 4],
    /// rgb emitted radiance, w = 1 when emitted from both faces.
    pub emission: [f32; 4],
    /// rgb reflectance of the glossy lobe, w = roughness (src/scene/brdf.rs).
    pub specular: [f32; 4],
}

/// The scene's albedo textures as one word array (shaders-glsl/common/texture.glsl reads it):
/// per texture a uvec4 (first texel word, width, height, 0), then every texture's RGBA8 texels.
fn texture_words(textures: &[&std::sync::Arc<crate::scene::Texture>]) -> Vec<u32> {
    let table = 4 * textures.len();
    let texels: usize = textures.iter().map(|t| t.texels.len()).sum();
    let mut words = Vec::with_capacity(table + texels);
    let mut first = table as u32;
    for t in textures {
        words.extend([first, t.width, t.height, 0]);
        first += t.texels.len() as u32;
    }
    for t in textures {
        words.extend_from_slice(&t.texels);
    }
    words
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    /// xyz position, w = kind (LIGHT_KIND_*).
    pub position_kind: [f32; 4],
    /// xyz unit axis, w = cos of the outer cone angle.
    pub direction_cos_outer: [f32; 4],
    /// rgb peak intensity (W/sr), w = cos of the inner cone angle.
    pub intensity_cos_inner: [f32; 4],
    /// x = first shadow view, y = shadow view count (1 for spot, 6 for point).
    pub shadow: [u32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuShadowView {
    pub view_projection: [[f32; 4]; 4],
    /// x = world-space size of a texel of a `map_size` map per unit distance from the light,
    /// y = near plane, z = far plane, w = 2 tan(fov / 2) (texel size times map size).
    pub params: [f32; 4],
    /// xyz = the view's axis, w = index of the light.
    pub axis_light: [f32; 4],
    /// xyz = the light's position (the view's eye), w = 1.
    pub origin: [f32; 4],
}

/// Extra field of view around a spot cone, so the cone edge lies inside the shadow map.
const SPOT_FOV_MARGIN_DEG: f32 = 4.0;

/// The spot light's local frame (axis, u, v): u and v span the plane across the axis. The same
/// construction is `light_frame` in shaders-glsl/common/lights.glsl.
pub fn light_frame(axis: Vec3) -> (Vec3, Vec3, Vec3) {
    let up = if axis.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
    let u = up.cross(axis).normalize();
    (axis, u, axis.cross(u))
}

/// Each light's first shadow view and number of views, as [`shadow_views`] lays them out (one
/// after another, in light order).
pub fn shadow_view_ranges(lights: &[Light]) -> Vec<(u32, u32)> {
    lights
        .iter()
        .scan(0, |first, light| {
            let range = (*first, light.shadow_view_count());
            *first += range.1;
            Some(range)
        })
        .collect()
}

/// One perspective view per spot light up to [`crate::scene::light::WIDE_SPOT_DEG`], five
/// faces of a cube around the axis for a wider one (front, then ±u, ±v of its frame), six
/// (cube faces) per point light.
pub fn shadow_views(
    scene: &Scene,
    scene_lights: &[Light],
    map_size: u32,
) -> (Vec<GpuLight>, Vec<GpuShadowView>) {
    let (lo, hi) = scene_lights
        .iter()
        .fold((scene.bounds_min, scene.bounds_max), |(lo, hi), l| {
            (lo.min(l.position), hi.max(l.position))
        });
    let extent = (hi - lo).length().max(1e-3);
    let mut lights = Vec::new();
    let mut views = Vec::new();
    for light in scene_lights {
        let first = views.len() as u32;
        let (cos_outer, cos_inner) = light.cone_cosines();
        let far_for = |p: Vec3| {
            let farthest = [lo.x, hi.x]
                .iter()
                .flat_map(|&x| [lo.y, hi.y].map(move |y| (x, y)))
                .flat_map(|(x, y)| [lo.z, hi.z].map(move |z| Vec3::new(x, y, z)))
                .map(|c| (c - p).length())
                .fold(0.0f32, f32::max);
            farthest * 1.01 + 1e-3
        };
        let far = far_for(light.position);
        let near = (extent * 1e-3).min(far * 0.01);
        let light_index = lights.len() as f32;
        let mut push_view = |dir: Vec3, up: Vec3, fov_deg: f32| {
            let view = look_at_mat4(light.position, light.position + dir, up);
            let proj = vulkan::perspective(fov_deg.to_radians(), 1.0, near, far);
            let extent = 2.0 * (0.5 * fov_deg.to_radians()).tan();
            views.push(GpuShadowView {
                view_projection: (proj * view).to_cols_array_2d(),
                params: [extent / map_size as f32, near, far, extent],
                axis_light: [dir.x, dir.y, dir.z, light_index],
                origin: light.position.extend(1.0).to_array(),
            });
        };
        let (kind, axis) = match light.kind {
            LightKind::Spot {
                direction,
                cone_angle_deg,
                ..
            } => {
                let axis = direction.normalize();
                if light.shadow_view_count() == 1 {
                    let up = if axis.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
                    push_view(axis, up, 2.0 * cone_angle_deg + SPOT_FOV_MARGIN_DEG);
                } else {
                    let (_, u, v) = light_frame(axis);
                    push_view(axis, u, 90.0);
                    for side in [u, -u, v, -v] {
                        push_view(side, axis, 90.0);
                    }
                }
                (LIGHT_KIND_SPOT, axis)
            }
            LightKind::Cosine { direction } => {
                let axis = direction.normalize();
                let (_, u, v) = light_frame(axis);
                push_view(axis, u, 90.0);
                for side in [u, -u, v, -v] {
                    push_view(side, axis, 90.0);
                }
                (LIGHT_KIND_COSINE, axis)
            }
            LightKind::Point => {
                // Face order matches the major-axis selection in lights.glsl: +x -x +y -y +z -z.
                let faces = [
                    (Vec3::X, Vec3::NEG_Y),
                    (Vec3::NEG_X, Vec3::NEG_Y),
                    (Vec3::Y, Vec3::Z),
                    (Vec3::NEG_Y, Vec3::NEG_Z),
                    (Vec3::Z, Vec3::NEG_Y),
                    (Vec3::NEG_Z, Vec3::NEG_Y),
                ];
                for (dir, up) in faces {
                    push_view(dir, up, 90.0);
                }
                (LIGHT_KIND_POINT, Vec3::NEG_Y)
            }
        };
        let intensity = light.intensity();
        lights.push(GpuLight {
            position_kind: [
                light.position.x,
                light.position.y,
                light.position.z,
                kind as f32,
            ],
            direction_cos_outer: [axis.x, axis.y, axis.z, cos_outer],
            intensity_cos_inner: [intensity.x, intensity.y, intensity.z, cos_inner],
            shadow: [first, views.len() as u32 - first, 0, 0],
        });
    }
    (lights, views)
}

/// The scene's geometry and lights in storage buffers.
pub struct SceneBuffers {
    /// The mesh's unique vertices.
    pub vertices: Buffer,
    /// Per triangle: its three vertex indices and its material (a uvec4).
    pub triangles: Buffer,
    pub materials: Buffer,
    /// Albedo textures: a table, then texels (see `texture_words`).
    pub textures: Buffer,
    pub lights: Buffer,
    pub shadow_views: Buffer,
    /// Vertices a draw of every triangle pulls (three per triangle).
    pub vertex_count: u32,
    pub light_count: u32,
    /// Shadow views of every light, in order (the shadow pass renders one layer per view).
    pub shadow_view_matrices: Vec<Mat4>,
    /// The position of the light each shadow view belongs to.
    pub shadow_view_origins: Vec<Vec3>,
}

impl SceneBuffers {
    /// The scene's geometry and materials, and `lights` (the scene's own for the path tracer;
    /// with area-light samples for the rasteriser, see [`Scene::raster_lights`]).
    pub fn upload(
        gpu: &Gpu,
        scene: &Scene,
        lights: &[Light],
        shadow_map_size: u32,
    ) -> GpuResult<SceneBuffers> {
        let mesh = &scene.mesh;
        let (textures, texture_of) = scene.textures();
        let materials: Vec<GpuMaterial> = scene
            .materials
            .iter()
            .zip(&texture_of)
            .map(|(m, texture)| GpuMaterial {
                albedo: m
                    .albedo
                    .extend(texture.map_or(0.0, |t| (t + 1) as f32))
                    .to_array(),
                emission: m
                    .emission
                    .extend(f32::from(u8::from(m.two_sided)))
                    .to_array(),
                specular: m.specular.extend(m.roughness).to_array(),
            })
            .collect();
        let (lights, views) = shadow_views(scene, lights, shadow_map_size);
        Ok(SceneBuffers {
            vertices: gpu.upload_storage_items("scene vertices", mesh.positions.len(), |i| {
                GpuVertex::of(mesh, i)
            })?,
            triangles: gpu.upload_storage_items("scene triangles", mesh.triangle_count(), |t| {
                let [a, b, c] = mesh.indices[t];
                [a, b, c, mesh.materials[t]]
            })?,
            materials: gpu.upload_storage("scene materials", bytemuck::cast_slice(&materials))?,
            textures: gpu.upload_storage(
                "scene textures",
                bytemuck::cast_slice(&texture_words(&textures)),
            )?,
            lights: gpu.upload_storage("scene lights", bytemuck::cast_slice(&lights))?,
            shadow_views: gpu.upload_storage("shadow views", bytemuck::cast_slice(&views))?,
            vertex_count: 3 * mesh.triangle_count() as u32,
            light_count: lights.len() as u32,
            shadow_view_matrices: Vec::new(),
            shadow_view_origins: Vec::new(),
        })
        .map(|mut buffers| {
            buffers.set_shadow_views(&views);
            buffers
        })
    }

    /// Keep the host-side copy of the shadow views (the RSM pass pushes them as constants).
    pub fn set_shadow_views(&mut self, views: &[GpuShadowView]) {
        self.shadow_view_matrices = views
            .iter()
            .map(|v| Mat4::from_cols_array_2d(&v.view_projection))
            .collect();
        self.shadow_view_origins = views
            .iter()
            .map(|v| Vec3::from_slice(&v.origin[..3]))
            .collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_texture_code_is_compiled_in_only_for_a_scene_with_a_texture() {
        let mut scene = Scene::load("cornell").unwrap();
        let textured = |scene: &Scene| texture_specialization(scene).value(SPEC_SCENE_TEXTURED);
        assert_eq!(textured(&scene), Some(0));
        let texture = crate::scene::Texture::new("white", 1, 1, vec![u32::MAX]).unwrap();
        scene.materials[0].albedo_texture = Some(std::sync::Arc::new(texture));
        assert_eq!(textured(&scene), Some(1));
    }

    #[test]
    fn shadow_view_ranges_follow_the_views_shadow_views_lays_out() {
        let scene = Scene::load("cornell").unwrap();
        let light = |kind| Light {
            position: Vec3::new(0.3, 0.5, 0.3),
            kind,
            flux: 1.0,
            color: Vec3::ONE,
        };
        let spot = |cone_angle_deg| LightKind::Spot {
            direction: Vec3::NEG_Y,
            cone_angle_deg,
            penumbra_deg: 5.0,
        };
        let lights = [
            light(LightKind::Point),
            light(spot(30.0)),
            light(spot(80.0)),
            light(LightKind::Cosine {
                direction: Vec3::NEG_Y,
            }),
            light(LightKind::Point),
        ];
        let (gpu_lights, views) = shadow_views(&scene, &lights, 256);
        let laid_out: Vec<(u32, u32)> = gpu_lights
            .iter()
            .map(|l| (l.shadow[0], l.shadow[1]))
            .collect();
        assert_eq!(shadow_view_ranges(&lights), laid_out);
        assert_eq!(views.len(), 6 + 1 + 5 + 5 + 6);
    }
}
