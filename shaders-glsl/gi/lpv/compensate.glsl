// Clamp compensation for the 26-neighbour step (compensation.glsl), in place, of the lattice a
// frame's first step propagates (the later steps' sources are compensated as their previous
// step stores them). The including shader defines
// CHANNELS (1: one colour channel a dispatch, at the _R bindings; 3: R, G and B in one) and
// LPV_TEXELS (1: the cells are read through their texel views, as the column kernel's
// lattices allow; 0: as storage buffers). Included by lpv/compensate{,_rgb}{,_texels}.comp.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = LINEAR_WORKGROUP) in;

struct Neighbour {
    vec4 transfer;
    ivec3 offset;
    float outscatter;
};

#define COMPENSATED_CELLS(binding_, block, name) \
    layout(binding = binding_, std430) buffer block { vec4 name[]; };
COMPENSATED_CELLS(COMPENSATE_CELLS_R, CellsR, cells_r)
#if CHANNELS == 3
COMPENSATED_CELLS(COMPENSATE_CELLS_G, CellsG, cells_g)
COMPENSATED_CELLS(COMPENSATE_CELLS_B, CellsB, cells_b)
#endif
#if LPV_TEXELS
// The same lattices as texels: lavapipe gathers a SIMD batch's texels with vector loads, where
// it loads a storage buffer lane by lane (docs/performance.md).
layout(binding = COMPENSATE_READ_R) uniform samplerBuffer read_r;
#if CHANNELS == 3
layout(binding = COMPENSATE_READ_G) uniform samplerBuffer read_g;
layout(binding = COMPENSATE_READ_B) uniform samplerBuffer read_b;
#endif
#define READ_CELL(texels, cells, i) texelFetch(texels, int(i))
#else
#define READ_CELL(texels, cells, i) cells[i]
#endif
layout(binding = COMPENSATE_NEIGHBOURS, std140) uniform Neighbours { Neighbour neighbours[26]; };

layout(push_constant) uniform Push {
    uint count;
    float keep_dc;           // 1 - λa
    float keep_directional;  // 1 - λa - λs
} pc;

// The neighbours' transfer vectors, read once at the top of main (docs/performance.md).
vec4 transfer[26];

vec4 compensation_transfer(int d) {
    return transfer[d];
}

#include "gi/lpv/compensation.glsl"

void main() {
    [[unroll]] for (int d = 0; d < 26; ++d) transfer[d] = neighbours[d].transfer;
    // No early return: with the rest under a branch, lavapipe took 2.7x this pass's time to read
    // the neighbours' uniform buffer and sum (docs/performance.md). An invocation past the
    // end computes the last cell again (reading it while its own invocation may write it; the
    // value is discarded) and stores nothing.
    uint i = min(gl_GlobalInvocationID.x, pc.count - 1u);
    bool stores = gl_GlobalInvocationID.x < pc.count;
    vec4 r = compensated(READ_CELL(read_r, cells_r, i), pc.keep_dc, pc.keep_directional);
#if CHANNELS == 3
    vec4 g = compensated(READ_CELL(read_g, cells_g, i), pc.keep_dc, pc.keep_directional);
    vec4 b = compensated(READ_CELL(read_b, cells_b, i), pc.keep_dc, pc.keep_directional);
#endif
    if (stores) {
        cells_r[i] = r;
#if CHANNELS == 3
        cells_g[i] = g;
        cells_b[i] = b;
#endif
    }
}
