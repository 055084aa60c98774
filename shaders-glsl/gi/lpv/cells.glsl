#ifndef VKGI_LPV_CELLS_GLSL
#define VKGI_LPV_CELLS_GLSL
// Where a propagation step reads and writes its lattices. The including shader defines
// CHANNELS (1: one colour channel a dispatch, bound at the _R bindings; 3: R, G and B in one
// dispatch, which reads the geometry once for all three) and LPV_TEXELS (1: the sources, the
// geometry and the accumulation are read as texel buffers; 0: as storage buffers). Lattices hold
// a vec4 (2-band SH) per cell, the geometry GEOMETRY_WORDS vec4 per cell (blocking.glsl).
//
// Texel fetches pay on lavapipe: it gathers the texels of a SIMD batch's lanes with vector
// loads and one vectorised bounds test, where a storage buffer's load is a loop over the lanes
// and components with a branch and a bounds test each. Stores stay storage-buffer stores (an
// image store measured slower there).
#include "gi/lpv/blocking.glsl"

// The light of one cell in each channel the step carries.
struct Light {
    vec4 c[CHANNELS];
};

Light no_light() {
    Light l;
    [[unroll]] for (int c = 0; c < CHANNELS; ++c) l.c[c] = vec4(0.0);
    return l;
}

#define WRITTEN_CELLS(binding_, block, name) \
    layout(binding = binding_, std430) writeonly buffer block { vec4 name[]; };
WRITTEN_CELLS(STEP_DESTINATION_R, DestinationR, destination_r)
#if CHANNELS == 3
WRITTEN_CELLS(STEP_DESTINATION_G, DestinationG, destination_g)
WRITTEN_CELLS(STEP_DESTINATION_B, DestinationB, destination_b)
#endif

#if LPV_TEXELS
layout(binding = STEP_GEOMETRY) uniform samplerBuffer geometry_cells;
layout(binding = STEP_SOURCE_R) uniform samplerBuffer source_r;
layout(binding = STEP_ACCUMULATION_READ_R) uniform samplerBuffer accumulation_read_r;
WRITTEN_CELLS(STEP_ACCUMULATION_R, AccumulationR, accumulation_r)
#if CHANNELS == 3
layout(binding = STEP_SOURCE_G) uniform samplerBuffer source_g;
layout(binding = STEP_SOURCE_B) uniform samplerBuffer source_b;
layout(binding = STEP_ACCUMULATION_READ_G) uniform samplerBuffer accumulation_read_g;
layout(binding = STEP_ACCUMULATION_READ_B) uniform samplerBuffer accumulation_read_b;
WRITTEN_CELLS(STEP_ACCUMULATION_G, AccumulationG, accumulation_g)
WRITTEN_CELLS(STEP_ACCUMULATION_B, AccumulationB, accumulation_b)
#endif
#define READ_CELL(name, k) texelFetch(name, int(k))
#define ACCUMULATION_OLD(read_name, name, i) texelFetch(read_name, int(i))
#else
#define READ_CELLS(binding_, block, name) \
    layout(binding = binding_, std430) readonly buffer block { vec4 name[]; };
#define ACCUMULATED_CELLS(binding_, block, name) \
    layout(binding = binding_, std430) buffer block { vec4 name[]; };
READ_CELLS(STEP_GEOMETRY, Geometry, geometry_cells)
READ_CELLS(STEP_SOURCE_R, SourceR, source_r)
ACCUMULATED_CELLS(STEP_ACCUMULATION_R, AccumulationR, accumulation_r)
#if CHANNELS == 3
READ_CELLS(STEP_SOURCE_G, SourceG, source_g)
READ_CELLS(STEP_SOURCE_B, SourceB, source_b)
ACCUMULATED_CELLS(STEP_ACCUMULATION_G, AccumulationG, accumulation_g)
ACCUMULATED_CELLS(STEP_ACCUMULATION_B, AccumulationB, accumulation_b)
#endif
#define READ_CELL(name, k) name[k]
#define ACCUMULATION_OLD(read_name, name, i) name[i]
#endif

// The light of lattice cell `k` in channel `c` (a constant once the channel loop is unrolled).
vec4 stored_light(uint k, int c) {
#if CHANNELS == 3
    if (c == 1) return READ_CELL(source_g, k);
    if (c == 2) return READ_CELL(source_b, k);
#endif
    return READ_CELL(source_r, k);
}

// Word `w` of the geometry of lattice cell `k`.
vec4 stored_geometry(uint k, uint w) {
    return READ_CELL(geometry_cells, k * GEOMETRY_WORDS + w);
}

// The geometry of lattice cell `k` where `inside`, zero elsewhere (and where the step blocks
// nothing).
GeometryWords stored_cell_geometry(uint k, bool inside) {
    GeometryWords g = no_geometry();
    for (uint w = 0u; w < GEOMETRY_READ_WORDS; ++w) g.w[w] = inside ? stored_geometry(k, w) : vec4(0.0);
    return g;
}

// 0 where nothing reads a step's result (one step a frame whose light is neither carried nor
// looked up: a two-scale near field, classic LPV of one step): the step writes only the
// accumulation. A constant, so the
// stores are compiled away (a branch would not skip them on lavapipe).
layout(constant_id = 7) const uint WRITES_RESULT = 1u;

// Cell `i`'s new light in every channel.
void store_light(uint i, Light light) {
    if (WRITES_RESULT == 0u) return;
    destination_r[i] = light.c[0];
#if CHANNELS == 3
    destination_g[i] = light.c[1];
    destination_b[i] = light.c[2];
#endif
}

// Add `light` to cell `i` of the accumulation in every channel.
void accumulate_light(uint i, Light light) {
    accumulation_r[i] = ACCUMULATION_OLD(accumulation_read_r, accumulation_r, i) + light.c[0];
#if CHANNELS == 3
    accumulation_g[i] = ACCUMULATION_OLD(accumulation_read_g, accumulation_g, i) + light.c[1];
    accumulation_b[i] = ACCUMULATION_OLD(accumulation_read_b, accumulation_b, i) + light.c[2];
#endif
}

#endif
