#version 460
// G-buffer: world position (w = 1 where covered), normal facing the camera, albedo, emission,
// glossy reflectance and roughness.
#include "common/scene.glsl"

layout(binding = RASTER_TEXTURES, std430) readonly buffer Textures { uint texture_words[]; };
#include "common/texture.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) flat in vec3 in_face_normal;
layout(location = 3) in vec2 in_texcoord;
layout(location = 4) flat in vec4 in_albedo;
layout(location = 5) flat in vec4 in_emission;
layout(location = 6) flat in vec4 in_specular;
layout(location = 7) flat in vec3 in_camera;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;
layout(location = 3) out vec4 out_emission;
layout(location = 4) out vec4 out_specular;

void main() {
    // Surfaces are two-sided: turn both normals toward the viewer.
    float facing = dot(in_face_normal, in_camera - in_position) >= 0.0 ? 1.0 : -1.0;
    vec3 n = shading_normal(in_normal, in_face_normal) * facing;
    if (dot(n, in_face_normal * facing) <= 0.0) n = in_face_normal * facing;
    Material m = Material(in_albedo, in_emission, in_specular);
    out_position = vec4(in_position, 1.0);
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(material_albedo(m, in_texcoord), 1.0);
    // Emission leaves the front face (by winding) only, unless the material is two-sided.
    bool emits = facing > 0.0 || m.emission.w > 0.5;
    out_emission = vec4(emits ? m.emission.rgb : vec3(0.0), 0.0);
    out_specular = m.specular;
}
