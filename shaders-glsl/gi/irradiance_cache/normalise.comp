#version 460
// The splat's normalisation (spec 003 §8.5 step 5): indirect radiance = albedo / pi · Σ w E' / Σ w
// added to the view's HDR image; pixels no record covers get none.
#include "common/math.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = IC_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = IC_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = IC_SPLAT, rgba32f) readonly uniform image2D splat;
layout(binding = IC_HDR, rgba32f) uniform image2D hdr;

layout(push_constant) uniform Push {
    uvec2 size;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    if (imageLoad(gbuffer_position, pixel).w == 0.0) return;
    vec4 sums = imageLoad(splat, pixel);
    if (!(sums.w > 0.0)) return;
    vec3 radiance = imageLoad(gbuffer_albedo, pixel).rgb * INV_PI * (sums.rgb / sums.w);
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
