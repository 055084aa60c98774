#ifndef VKGI_RADIOSITY_DISPLAY_GLSL
#define VKGI_RADIOSITY_DISPLAY_GLSL
// Indirect light per pixel (spec 004 pass A6), shared by the display as a pass of its own
// (radiosity/display.comp) and drawn inside direct lighting (radiosity/lit_display.frag): the
// pixel's triangle gives its patch, the side facing the eye its surface; the surface's
// indirect irradiance is interpolated bilinearly between the grid's texels that lie on the
// polygon, and the ambient term still to arrive is added.
#include "gi/radiosity/radiosity.glsl"

// Everything read as texels, bit for bit (floats through uintBitsToFloat): lavapipe reads a
// storage buffer at an index that differs across lanes lane by lane, in a loop with a branch a
// lane.
layout(binding = RAD_SURFACES) uniform usamplerBuffer surfaces;
layout(binding = RAD_ELEMENTS) uniform usamplerBuffer elements;
layout(binding = RAD_INDIRECT) uniform usamplerBuffer indirect;
layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
// Per mesh triangle two texels: its patch's normal (float bits) and its front side's surface,
// then its back side's surface (src/gi/radiosity/mod.rs triangle_sides).
layout(binding = RAD_TRIANGLE_SIDES) uniform usamplerBuffer triangle_sides;
layout(binding = RAD_TRIANGLE_IDS, r32ui) readonly uniform uimage2D triangle_ids;

// The indirect irradiance at the surface point `position` that `pixel` shows, seen from `eye`,
// with the ambient term still to arrive where `ambient`: false where no patch's triangle covers
// the pixel (nothing to add).
bool display_irradiance(ivec2 pixel, vec3 position, vec3 eye, bool ambient, out vec3 irradiance) {
    irradiance = vec3(0.0);
    uint triangle = imageLoad(triangle_ids, pixel).x;
    if (triangle == 0u) return false;
    int sides = 2 * int(triangle - 1u);
    uvec4 front = texelFetch(triangle_sides, sides);
    bool back = dot(uintBitsToFloat(front.xyz), eye - position) < 0.0;
    uint s = back ? texelFetch(triangle_sides, sides + 1).x : front.w;
    if (ambient) irradiance = shot.ambient.rgb;
    if (s != NO_SURFACE) {
        int record = 6 * int(s);
        vec4 origin_texel = uintBitsToFloat(texelFetch(surfaces, record));
        vec3 axis_t = uintBitsToFloat(texelFetch(surfaces, record + 1).xyz);
        vec3 axis_b = uintBitsToFloat(texelFetch(surfaces, record + 2).xyz);
        uvec4 grid = texelFetch(surfaces, record + 5);
        vec3 local = position - origin_texel.xyz;
        vec2 texel = vec2(dot(local, axis_t), dot(local, axis_b)) / origin_texel.w - 0.5;
        ivec2 base = ivec2(floor(texel));
        vec2 f = texel - vec2(base);
        vec4 sum = vec4(0.0);
        for (int k = 0; k < 4; k++) {
            ivec2 at = base + ivec2(k & 1, k >> 1);
            if (any(lessThan(at, ivec2(0))) || at.x >= int(grid.y) || at.y >= int(grid.z)) continue;
            uint e = grid.x + uint(at.y) * grid.y + uint(at.x);
            if (uintBitsToFloat(texelFetch(elements, 2 * int(e)).w) <= 0.0) continue;
            float w = ((k & 1) != 0 ? f.x : 1.0 - f.x) * ((k >> 1) != 0 ? f.y : 1.0 - f.y);
            w = max(w, 1e-6);
            sum += vec4(uintBitsToFloat(texelFetch(indirect, int(e)).rgb) * w, w);
        }
        if (sum.w > 0.0) irradiance += sum.rgb / sum.w;
    }
    return true;
}

#endif
