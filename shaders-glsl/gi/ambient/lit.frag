#version 460
// Direct lighting and the constant-ambient baseline in one pass: the frame's direct radiance
// (raster/lighting_pixel.glsl) plus albedo * E / pi at the surface it read, written once to the
// HDR image. Against direct lighting followed by ambient/lookup.comp it reads the G-buffer once
// and writes the HDR image once; the same sum.
#include "raster/lighting_pixel.glsl"

layout(location = LIGHTING_VARYING_WORDS) flat in vec4 irradiance;

layout(location = 0) out vec4 out_radiance;

void main() {
    vec4 position;
    Surface s;
    vec3 direct = direct_radiance(ivec2(gl_FragCoord.xy), position, s);
    vec3 ambient = s.albedo * irradiance.rgb * INV_PI;
    // Background pixels (w = 0) get no indirect light.
    out_radiance = vec4(direct + (position.w != 0.0 ? ambient : vec3(0.0)), 1.0);
}
