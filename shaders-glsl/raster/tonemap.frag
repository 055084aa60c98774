#version 460
// Exposure, Reinhard L/(1+L) per channel, sRGB encoding into the 8-bit output image: a fragment
// pass over a full-screen triangle (common/fullscreen.vert) with that image as render target.
#include "common/color.glsl"

layout(binding = TONEMAP_HDR_IN, rgba32f) readonly uniform image2D hdr_in;
layout(location = 0) out vec4 out_ldr;

layout(push_constant) uniform Push {
    float exposure_scale;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 radiance = imageLoad(hdr_in, pixel).rgb * pc.exposure_scale;
    out_ldr = vec4(srgb_encode(tonemap_reinhard(radiance)), 1.0);
}
