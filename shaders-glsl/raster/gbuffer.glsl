#ifndef VKGI_RASTER_GBUFFER_GLSL
#define VKGI_RASTER_GBUFFER_GLSL
// G-buffer: world position (w = 1 where covered), normal facing the camera, albedo, and with
// MATERIAL_TERMS emission, glossy reflectance and roughness. A scene whose materials have
// neither writes three targets (raster/gbuffer_plain.frag): its emission and glossy targets
// keep the zeros they were cleared to (src/render/targets.rs), and the pass takes 30% less
// time on lavapipe (docs/performance.md).
#include "common/scene.glsl"

layout(binding = RASTER_TEXTURES, std430) readonly buffer Textures { uint texture_words[]; };
#include "common/texture.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) flat in vec3 in_face_normal;
layout(location = 3) in vec2 in_texcoord;
layout(location = 4) flat in vec4 in_albedo;
#ifdef MATERIAL_TERMS
layout(location = 5) flat in vec4 in_emission;
layout(location = 6) flat in vec4 in_specular;
#endif
layout(location = 7) flat in vec3 in_camera;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;
#ifdef MATERIAL_TERMS
layout(location = 3) out vec4 out_emission;
layout(location = 4) out vec4 out_specular;
#endif

void main() {
    // Surfaces are two-sided: turn both normals toward the viewer.
    float facing = dot(in_face_normal, in_camera - in_position) >= 0.0 ? 1.0 : -1.0;
    vec3 n = shading_normal(in_normal, in_face_normal) * facing;
    if (dot(n, in_face_normal * facing) <= 0.0) n = in_face_normal * facing;
#ifdef MATERIAL_TERMS
    Material m = Material(in_albedo, in_emission, in_specular);
#else
    Material m = Material(in_albedo, vec4(0.0), vec4(0.0));
#endif
    out_position = vec4(in_position, 1.0);
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(material_albedo(m, in_texcoord), 1.0);
#ifdef MATERIAL_TERMS
    // Emission leaves the front face (by winding) only, unless the material is two-sided.
    bool emits = facing > 0.0 || m.emission.w > 0.5;
    out_emission = vec4(emits ? m.emission.rgb : vec3(0.0), 0.0);
    out_specular = m.specular;
#endif
}

#endif
