#version 460
// Tone mapping as a compute pass, the form a GPU runs (src/gpu/context.rs, PixelPasses), where
// raster/tonemap.frag is the fragment form: the same exposure and Reinhard L/(1+L) per channel,
// the sRGB encoding done here (the fragment form's attachment does it) before the store to the
// 8-bit image's UNORM view.
#include "common/color.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = TONEMAP_HDR_IN, rgba32f) readonly uniform image2D hdr_in;
layout(binding = TONEMAP_LDR_OUT, rgba8) writeonly uniform image2D ldr_out;

layout(push_constant) uniform Push {
    float exposure_scale;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(ldr_out)))) return;
    vec3 radiance = imageLoad(hdr_in, pixel).rgb * pc.exposure_scale;
    imageStore(ldr_out, pixel, vec4(srgb_encode(tonemap_reinhard(radiance)), 1.0));
}
