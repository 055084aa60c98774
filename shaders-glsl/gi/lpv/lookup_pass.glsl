#ifndef VKGI_LPV_LOOKUP_PASS_GLSL
#define VKGI_LPV_LOOKUP_PASS_GLSL
// Indirect light from the lattice (lpv/lookup_light.glsl) added to the HDR image: a fragment
// pass over a full-screen triangle (lpv/lookup.vert, which hands it the fields' constants as
// flat varyings) whose output the blend adds to the HDR image. The frame draws it where direct
// lighting is a compute pass, or when asked to draw the lookup apart; otherwise
// lpv/lit_lookup.frag adds the same light inside the direct-lighting pass.
#include "gi/lpv/lookup_light.glsl"
#include "gi/lpv/lookup_surface.glsl"

// Added to the HDR image by the blend (one plus one).
layout(location = 0) out vec4 out_indirect;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = surface_position(pixel);
    vec3 n = surface_normal(pixel);
    vec3 albedo = surface_albedo(pixel);
    vec3 value = lattice_radiance(position.xyz, n, albedo);
    // Background pixels (w = 0) get nothing.
    out_indirect = vec4(position.w != 0.0 ? value : vec3(0.0), 0.0);
}

#endif
