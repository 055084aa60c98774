#version 460
// The half-resolution lookup's light (lpv/lookup_half.frag) spread over the full-resolution
// pixels (lpv/upsample.glsl), times albedo, added to the HDR image by the blend: the lookup apart
// from direct lighting at --lookup-resolution half (lpv/lit_upsample.frag draws it inside).
#include "gi/lpv/upsample.glsl"

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(push_constant) uniform Push {
    vec4 eye;
} pc;

// Added to the HDR image by the blend (one plus one).
layout(location = 0) out vec4 out_indirect;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 value = albedo * upsampled_light(pixel, position.xyz, n, pc.eye.xyz);
    // Background pixels (w = 0) get nothing.
    out_indirect = vec4(position.w != 0.0 ? value : vec3(0.0), 0.0);
}
