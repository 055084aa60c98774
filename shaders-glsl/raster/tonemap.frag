#version 460
// Exposure and Reinhard L/(1+L) per channel into the 8-bit output image: a fragment pass over a
// full-screen triangle (common/fullscreen.vert) whose render target is that image's sRGB view
// (src/render/targets.rs), so the attachment does the sRGB encoding (IEC 61966-2-1).
#include "common/color.glsl"

layout(binding = TONEMAP_HDR_IN, rgba32f) readonly uniform image2D hdr_in;
layout(location = 0) out vec4 out_ldr;

layout(push_constant) uniform Push {
    float exposure_scale;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 radiance = imageLoad(hdr_in, pixel).rgb * pc.exposure_scale;
    out_ldr = vec4(tonemap_reinhard(radiance), 1.0);
}
