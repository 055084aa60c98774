#ifndef VKGI_LPV_LIT_LOOKUP_PASS_GLSL
#define VKGI_LPV_LIT_LOOKUP_PASS_GLSL
// Direct lighting and the lookup in one pass: the frame's direct radiance
// (raster/lighting_pixel.glsl) plus the lattice's indirect radiance (lpv/lookup_light.glsl) at
// the surface it read, written once to the HDR image. Against direct lighting followed by
// lpv/lookup.frag it reads the G-buffer once and draws one pass instead of two; the same sum.
#define LOOKUP_FIELDS_LOCATION LIGHTING_VARYING_WORDS
#include "raster/lighting_pixel.glsl"
#include "gi/lpv/lookup_light.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    vec4 position;
    Surface s;
    vec3 direct = direct_radiance(ivec2(gl_FragCoord.xy), position, s);
    vec3 indirect = lattice_radiance(position.xyz, s.n, s.albedo);
    // Background pixels (w = 0) get no indirect light.
    out_radiance = vec4(direct + (position.w != 0.0 ? indirect : vec3(0.0)), 1.0);
}

#endif
