#ifndef VKGI_RADIOSITY_GLSL
#define VKGI_RADIOSITY_GLSL
// Layouts shared by the radiosity passes; the Rust side is src/gi/radiosity/solver.rs.
#include "common/sampling.glsl"

// One side of a patch: a shooter and the owner of a width x height grid of elements.
struct SurfaceRecord {
    vec4 origin_texel;   // xyz corner of texel (0, 0), w = texel side
    vec4 axis_t_area;    // xyz grid x axis (unit), w = area (sum of its elements')
    vec4 axis_b;         // xyz grid y axis (unit)
    vec4 normal;         // xyz outward normal of this side
    vec4 emission;       // rgb emitted radiosity (W/m²)
    uvec4 grid;          // x first element, y width, z height, w shooting level (blocks of 2^w)
};

// A texel of a surface's grid; area 0 outside the polygon.
struct Element {
    vec4 position_area;  // xyz centroid, w = area
    vec4 albedo_surface; // rgb albedo, w = the surface's index (as float bits)
};

// Where the current shot leaves from.
#define LOCATION_NONE 0.0
#define LOCATION_SURFACE 1.0
#define LOCATION_LIGHT 2.0
struct Location {
    vec4 position_area;  // xyz position, w = the disc's area (surface shots)
    vec4 normal_kind;    // xyz the hemisphere's axis, w = LOCATION_*
    vec4 emitted;        // surface: rgb unshot emission; light: rgb peak intensity, w = cos inner
    vec4 reflected;      // surface: rgb unshot reflected radiosity; light: xyz spot axis, w = cos outer
};

// The solver's state, written by the selection pass.
#define NO_SHOOTER 0xffffffffu
struct Shot {
    uint shooter;        // surface shooting now, or NO_SHOOTER (converged)
    uint level;
    uint blocks_x;
    uint blocks_y;
    vec4 ambient;        // rgb the ambient irradiance still to arrive (display only)
    vec4 power;          // x unshot power now, y the most there was, z the shooter's, w shots done
    uvec4 table;         // pd: x table columns waiting for a delivery as of the last pick, y the
                         // view generation that pick saw
};

// What a shot carries: unshot radiosity, or unshot importance (the id and pd modes, spec 004
// pass B2: shot like radiosity, scaled by the receiver's mean albedo).
#define QUANTITY_RADIOSITY 0u
#define QUANTITY_IMPORTANCE 1u

// Gather flags (pd, spec 004 §6): receivers outside the simulated field of view are skipped
// (their share waits in the stored table); a delivery shoots table entries instead.
#define GATHER_RESTRICT 1u
#define GATHER_DELIVER 2u

// The stored radiosity table (pd, spec 004 §6.2): column c = shooter x location slots + slot,
// entry (c, j) the unshot radiosity location c shot while receiver surface j was out of view.
struct TableEntry {
    vec4 emitted;        // rgb
    vec4 reflected;      // rgb
};

// The column being delivered (pd, §6.5).
#define NO_COLUMN 0xffffffffu
struct Delivery {
    uint column;         // or NO_COLUMN
    uint pending;        // columns with entries for receivers now in view (this one included)
    uint generation;     // counts the simulated view's changes (written by the CPU)
    uint pad;
};

// A patch side without elements (no light reaches it).
#define NO_SURFACE 0xffffffffu

// Item-buffer values: 0 = nothing drawn; a side no light reaches still occludes.
#define ITEM_UNREACHED 0xffffffffu

// The hemicube's faces: 0 looks along n, 1-4 along +t, -t, +b, -b (forward, right, up).
void hemicube_axes(uint face, vec3 n, vec3 t, vec3 b, out vec3 f, out vec3 r, out vec3 u) {
    if (face == 0u) { f = n; r = t; u = b; }
    else if (face == 1u) { f = t; r = b; u = n; }
    else if (face == 2u) { f = -t; r = -b; u = n; }
    else if (face == 3u) { f = b; r = -t; u = n; }
    else { f = -b; r = t; u = n; }
}

// Stereographic projection of unit direction d (above the horizon) onto the unit disc.
vec2 stereographic(vec3 d, vec3 n, vec3 t, vec3 b) {
    return vec2(dot(d, t), dot(d, b)) / max(1.0 + dot(d, n), 1e-6);
}

// Layer and pixel of the item buffer (side `resolution`) that unit direction d falls in.
ivec3 item_texel(vec3 d, vec3 n, bool hemicube, uint resolution) {
    vec3 t, b;
    orthonormal_basis(n, t, b);
    vec2 ndc;
    uint layer = 0u;
    if (hemicube) {
        float best = dot(d, n);
        float along[4] = float[4](dot(d, t), -dot(d, t), dot(d, b), -dot(d, b));
        for (uint i = 0u; i < 4u; i++) {
            if (along[i] > best) { best = along[i]; layer = i + 1u; }
        }
        vec3 f, r, u;
        hemicube_axes(layer, n, t, b, f, r, u);
        ndc = vec2(dot(d, r), dot(d, u)) / max(dot(d, f), 1e-9);
    } else {
        ndc = stereographic(d, n, t, b);
    }
    ivec2 pixel = ivec2(floor((ndc * 0.5 + 0.5) * float(resolution)));
    return ivec3(clamp(pixel, ivec2(0), ivec2(int(resolution) - 1)), int(layer));
}

float mean3(vec3 v) {
    return (v.x + v.y + v.z) / 3.0;
}

#endif
