#version 460
// The constant-ambient baseline: every surface receives the same irradiance E (per channel), so
// its indirect radiance is albedo * E / pi, added to the HDR image.
#include "common/math.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = AMBIENT_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = AMBIENT_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = AMBIENT_HDR, rgba32f) uniform image2D hdr;

layout(push_constant) uniform Push {
    vec4 irradiance;    // rgb: E per channel (W/m²)
    uvec2 size;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    if (imageLoad(gbuffer_position, pixel).w == 0.0) return;
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 radiance = albedo * pc.irradiance.rgb * INV_PI;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
