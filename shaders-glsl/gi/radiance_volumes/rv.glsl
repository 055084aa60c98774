#ifndef VKGI_RV_GLSL
#define VKGI_RV_GLSL
// What the allocation and apply passes share, so both place a point in the same cascade, cell
// and corners (spec 001 §4.2 (c)): the cascades (src/gi/radiance_volumes/cascades.rs mirrors
// `rv_cascade`, `rv_select` and `rv_cell`) and the address volume's layout.

// The cascades of one frame, as every pass that places points gets them in its push constants
// (the boxes are derived here, never stored, so allocation and apply compute them alike).
struct RvGrid {
    vec3 eye;           // the cascades' centre
    float first_side;   // side of cascade 0; cascade i is 2^i times as wide
    uint count;         // cascades
    uint resolution;    // cells per side
    float transition;   // cells over which a cascade blends into the next (0: none)
};

struct Cascade {
    vec3 lo;            // snapped grid minimum
    float cell;         // cell size
    vec3 decision_lo;   // the unsnapped decision box
    vec3 decision_hi;
};

const uint RV_NONE = 0xFFFFFFFFu;

Cascade rv_cascade(RvGrid grid, uint i) {
    float side = grid.first_side * float(1u << i);
    float cell = side / float(grid.resolution);
    float half_decision = 0.5 * side - 1.5 * cell;
    return Cascade((floor(grid.eye / cell + 0.5) + 0.5) * cell - 0.5 * side, cell,
                   grid.eye - half_decision, grid.eye + half_decision);
}

// The cascade serving p (RV_NONE beyond the last cascade's grid) and the weight of the next
// cascade near the decision box's faces.
uint rv_select(RvGrid grid, vec3 p, out float blend) {
    blend = 0.0;
    for (uint i = 0u; i + 1u < grid.count; ++i) {
        Cascade c = rv_cascade(grid, i);
        if (all(greaterThanEqual(p, c.decision_lo)) && all(lessThanEqual(p, c.decision_hi))) {
            if (grid.transition > 0.0) {
                vec3 inside = min(p - c.decision_lo, c.decision_hi - p);
                float d = min(inside.x, min(inside.y, inside.z));
                blend = clamp(1.0 - d / (c.cell * grid.transition), 0.0, 1.0);
            }
            return i;
        }
    }
    Cascade last = rv_cascade(grid, grid.count - 1u);
    vec3 hi = last.lo + vec3(last.cell * float(grid.resolution));
    return all(greaterThanEqual(p, last.lo)) && all(lessThanEqual(p, hi)) ? grid.count - 1u : RV_NONE;
}

// The cell of cascade i holding p and p's position inside it.
void rv_cell(RvGrid grid, uint i, vec3 p, out uvec3 g, out vec3 f) {
    Cascade c = rv_cascade(grid, i);
    vec3 u = (p - c.lo) / c.cell;
    vec3 cell = clamp(floor(u), vec3(0.0), vec3(float(grid.resolution - 1u)));
    g = uvec3(cell);
    f = clamp(u - cell, 0.0, 1.0);
}

// Index of corner `corner` of cascade i in the address volume ((N+1)^3 corners per cascade).
uint rv_corner_index(uint i, uvec3 corner, uint resolution) {
    uint side = resolution + 1u;
    return i * side * side * side + corner.x + side * (corner.y + side * corner.z);
}

#endif
