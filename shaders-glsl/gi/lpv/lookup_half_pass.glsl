#ifndef VKGI_LPV_LOOKUP_HALF_PASS_GLSL
#define VKGI_LPV_LOOKUP_HALF_PASS_GLSL
// The lookup at half resolution (--lookup-resolution half): per texel (x, y) of a quarter-size
// target, the lattices' light per unit albedo (lpv/lookup_light.glsl) at the surface of
// full-resolution pixel (2x, 2y), with that surface's distance from the eye and its normal
// (lpv/half_light.glsl), for lpv/upsample.glsl to spread over the full-resolution pixels.
#include "gi/lpv/lookup_light.glsl"
#include "gi/lpv/half_light.glsl"
#define LOOKUP_READS_ALBEDO 0
#include "gi/lpv/lookup_surface.glsl"

layout(push_constant) uniform Push {
    vec4 eye;
} pc;

layout(location = 0) out uvec4 out_light;

void main() {
    ivec2 pixel = 2 * ivec2(gl_FragCoord.xy);
    vec4 position = surface_position(pixel);
    vec3 n = surface_normal(pixel);
    vec3 light = lattice_radiance(position.xyz, n, vec3(1.0));
    // Background pixels (w = 0): no light, and a distance no surface is alike to.
    out_light = position.w != 0.0
        ? pack_half_light(light, distance(position.xyz, pc.eye.xyz), n)
        : pack_half_light(vec3(0.0), UPSAMPLE_NO_SURFACE, vec3(0.0, 0.0, 1.0));
}

#endif
