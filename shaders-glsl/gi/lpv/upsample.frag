#version 460
// The half-resolution lookup's light (lpv/lookup_half.frag) spread over the full-resolution
// pixels (lpv/upsample.glsl), times albedo, added to the HDR image by the blend: the lookup apart
// from direct lighting at --lookup-resolution half (lpv/lit_upsample.frag draws it inside).
#include "gi/lpv/upsample.glsl"
#include "gi/lpv/lookup_surface.glsl"

layout(push_constant) uniform Push {
    vec4 eye;
} pc;

// Added to the HDR image by the blend (one plus one).
layout(location = 0) out vec4 out_indirect;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = surface_position(pixel);
    vec3 n = surface_normal(pixel);
    vec3 albedo = surface_albedo(pixel);
    vec3 value = albedo * upsampled_light(pixel, position.xyz, n, pc.eye.xyz);
    // Background pixels (w = 0) get nothing.
    out_indirect = vec4(position.w != 0.0 ? value : vec3(0.0), 0.0);
}
