#version 460
// Reflective shadow map (Dachsbacher & Stamminger 2005) of one light view: world position,
// normal (toward the light) and the flux the texel's surface reflects: albedo times the light's
// intensity toward it times the texel's solid angle (exact for a perspective texel:
// (extent / size)² cos³ of the angle to the view axis). Runs with rsm.vert, whose "camera
// position" is the light's position here.
#include "common/scene.glsl"

layout(binding = RSM_TEXTURES, std430) readonly buffer Textures { uint texture_words[]; };
#include "common/texture.glsl"
#include "common/lights.glsl"

layout(binding = RSM_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = RSM_VIEWS, std430) readonly buffer ShadowViews { ShadowView views[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 camera_position;   // the light's position
    uint view;
    uint size;
} pc;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) flat in vec3 in_face_normal;
layout(location = 3) in vec2 in_texcoord;
layout(location = 4) flat in vec4 in_albedo;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;

void main() {
    ShadowView view = views[pc.view];
    Light light = lights[uint(view.axis_light.w)];
    float facing = dot(in_face_normal, pc.camera_position.xyz - in_position) >= 0.0 ? 1.0 : -1.0;
    vec3 n = shading_normal(in_normal, in_face_normal) * facing;
    if (dot(n, in_face_normal * facing) <= 0.0) n = in_face_normal * facing;
    vec3 to_light;
    float distance;
    vec3 irradiance_factor = light_incidence(light, in_position, to_light, distance);
    float cos_axis = max(dot(view.axis_light.xyz, -to_light), 0.0);
    float texel = view.params.w / float(pc.size);
    float solid_angle = texel * texel * cos_axis * cos_axis * cos_axis;
    vec3 intensity = irradiance_factor * distance * distance;
    out_position = vec4(in_position, 1.0);
    out_normal = vec4(n, 0.0);
    out_flux = vec4(material_albedo(Material(in_albedo, vec4(0.0), vec4(0.0)), in_texcoord) * intensity * solid_angle, 0.0);
}
