#ifndef VKGI_RV_GLSL
#define VKGI_RV_GLSL
// What the allocation and apply passes share, so both place a point in the same cascade, cell
// and corners (spec 001 §4.2 (c)): the cascades (src/gi/radiance_volumes/cascades.rs, which
// mirrors `rv_select` and `rv_cell`) and the address volume's layout.

struct Cascade {
    vec4 min_cell;      // xyz snapped grid minimum, w cell size
    vec4 decision_min;  // xyz decision-box minimum, w transition width in cells
    vec4 decision_max;  // xyz decision-box maximum
};

#include "gi/radiance_volumes/state.glsl"

layout(binding = RV_CASCADES, std430) readonly buffer Cascades { Cascade cascades[]; };

const uint RV_NONE = 0xFFFFFFFFu;

// The cascade serving p (RV_NONE beyond the last cascade's grid) and the weight of the next
// cascade near the decision box's faces.
uint rv_select(vec3 p, uint count, uint resolution, out float blend) {
    blend = 0.0;
    for (uint i = 0u; i + 1u < count; ++i) {
        Cascade c = cascades[i];
        vec3 lo = c.decision_min.xyz;
        vec3 hi = c.decision_max.xyz;
        if (all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi))) {
            float transition = c.decision_min.w;
            if (transition > 0.0) {
                vec3 inside = min(p - lo, hi - p);
                float d = min(inside.x, min(inside.y, inside.z));
                blend = clamp(1.0 - d / (c.min_cell.w * transition), 0.0, 1.0);
            }
            return i;
        }
    }
    Cascade last = cascades[count - 1u];
    vec3 lo = last.min_cell.xyz;
    vec3 hi = lo + vec3(last.min_cell.w * float(resolution));
    return all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi)) ? count - 1u : RV_NONE;
}

// The cell of cascade i holding p and p's position inside it.
void rv_cell(uint i, vec3 p, uint resolution, out uvec3 g, out vec3 f) {
    Cascade c = cascades[i];
    vec3 u = (p - c.min_cell.xyz) / c.min_cell.w;
    vec3 cell = clamp(floor(u), vec3(0.0), vec3(float(resolution - 1u)));
    g = uvec3(cell);
    f = clamp(u - cell, 0.0, 1.0);
}

// Index of corner `corner` of cascade i in the address volume ((N+1)^3 corners per cascade).
uint rv_corner_index(uint i, uvec3 corner, uint resolution) {
    uint side = resolution + 1u;
    return i * side * side * side + corner.x + side * (corner.y + side * corner.z);
}

vec3 rv_corner_position(uint i, uvec3 corner) {
    Cascade c = cascades[i];
    return c.min_cell.xyz + vec3(corner) * c.min_cell.w;
}

#endif
