#version 460
// The display as a pass of its own (radiosity/display.glsl): albedo / pi times the indirect
// irradiance added to the HDR image, where direct lighting is a compute pass (GPUs) or the
// frame asks for the passes apart.
#include "gi/radiosity/display.glsl"
#include "common/math.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = RAD_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = RAD_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = RAD_HDR, rgba32f) uniform image2D hdr;

layout(push_constant) uniform Push {
    vec4 eye;        // xyz
    uvec2 size;
    uint ambient;    // 1: add the ambient term
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0) return;
    vec3 irradiance;
    if (!display_irradiance(pixel, position.xyz, pc.eye.xyz, pc.ambient != 0u, irradiance)) return;
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(albedo * irradiance * INV_PI, 0.0));
}
