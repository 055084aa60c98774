// One 26-neighbour ILPV gather step for one colour channel, or all three (CHANNELS, cells.glsl)
// (seed 000, Listing 5.2/5.3): each destination cell gathers from its 26 neighbours, with
// absorption and scattering, blocking by the source cell's geometry (blocking.glsl), negative
// transfers clamped to zero (the transported light alone: the in-scattered light adds to it,
// see cpu.rs). src/gi/lpv/cpu.rs step_26 is the same in f64. With `accumulate`, the result is also summed into the accumulation
// lattice the lookup reads. Included by lpv/ilpv_{tiled,naive,column}{,_rgb}.comp.

#extension GL_EXT_control_flow_attributes : require
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

struct Neighbour {
    vec4 transfer;    // Γ_j (κ-scaled)
    ivec3 offset;     // neighbour direction
    float outscatter; // γ_j
};

layout(binding = STEP_CONSTANTS, std140) uniform Neighbours { Neighbour neighbours[26]; };

layout(push_constant) uniform Push {
    ivec4 dims;
    float keep;            // 1 - λs - λa
    float scatter_energy;  // 2 sqrt(pi) λs
    uint accumulate;       // 1: also add the result to the accumulation lattice
    float keep_dc;         // the clamp compensation's medium, 1 - λa
    float keep_directional;  // 1 - λa - λs
    uint compensate_result;  // 1: store the result compensated (a step follows this one)
} pc;

#include "gi/lpv/tile.glsl"

// 0 where the clamp compensation applies the medium before the step (or there is none): the
// step then only transports (keep 1, no outscattering), and the terms that would multiply by 1
// and add 0 are compiled away (the same bits for finite cells).
layout(constant_id = 8) const uint STEP_MEDIUM = 1u;

// The neighbours' constants, read by load_step_constants() at the top of main, outside every
// branch and loop: read where they are used, inside the column's loop, they cost lavapipe
// 1.5x this step's time (docs/performance.md).
vec4 neighbour_transfer[26];
float neighbour_outscatter[26];

void load_step_constants() {
    [[unroll]] for (int d = 0; d < 26; ++d) {
        neighbour_transfer[d] = neighbours[d].transfer;
        neighbour_outscatter[d] = neighbours[d].outscatter;
    }
}

vec4 compensation_transfer(int d) {
    return neighbour_transfer[d];
}

#include "gi/lpv/compensation.glsl"

// 1 where the clamp compensation applies the medium and the step stores its result: the steps
// then store their results compensated for the next (pc.compensate_result, 0 in the last step,
// whose result goes on raw), so that only a frame's first source needs a compensation pass.
layout(constant_id = 10) const uint COMPENSATES_RESULT = 0u;

// What the step stores of `light`: as the compensation pass would leave it for the next step
// where one follows (the same function: the same bits), as it is otherwise.
Light stored_result(Light light) {
    if (COMPENSATES_RESULT == 0u) return light;
    Light stored;
    [[unroll]] for (int c = 0; c < CHANNELS; ++c) {
        vec4 next = compensated(light.c[c], pc.keep_dc, pc.keep_directional);
        stored.c[c] = pc.compensate_result != 0u ? next : light.c[c];
    }
    return stored;
}

// The d-th of the 26 offsets in {-1,0,1}³ without the centre, x fastest (transfer.rs offsets).
ivec3 neighbour_offset(int d) {
    int i = d < 13 ? d : d + 1;
    return ivec3(i % 3, (i / 3) % 3, i / 9) - 1;
}

// Adds to `dst` the light `cell` gathers from neighbour `d`, in every channel the step carries
// (the blocking, which depends on the geometry alone, once for all of them). `own_geometry` is
// the cell's own (read by the visibility model alone).
void add_neighbour(ivec3 cell, int d, GeometryWords own_geometry, inout Light dst) {
    vec4 transfer = neighbour_transfer[d];
    ivec3 offset = neighbour_offset(d);
    float blocked = blocking_of(source_geometry(cell, -offset), own_geometry, transfer, offset);
    float blocking = passing_share(blocked);
    [[unroll]] for (int c = 0; c < CHANNELS; ++c) {
        vec4 src = source_light(cell, -offset, c);
        float transported = max(dot(src, transfer), 0.0);
        if (STEP_MEDIUM != 0u) {
            float outscattered = src.x * pc.scatter_energy;
            transported = max(pc.keep * dot(src, transfer), 0.0)
                          + outscattered * neighbour_outscatter[d];
        }
        dst.c[c] += transfer * (transported * blocking);
    }
}

// The gathered light of `cell` from its 26 neighbours, in the x-fastest order of their offsets
// (transfer.rs). Unrolled: every neighbour offset is a constant.
Light gather(ivec3 cell) {
    GeometryWords own_geometry = source_geometry(cell, ivec3(0));
    Light dst = no_light();
    [[unroll]] for (int d = 0; d < 26; ++d) add_neighbour(cell, d, own_geometry, dst);
    return dst;
}

// Adds to `dst` the part of gather(cell) from the neighbours in plane group `group` (a
// constant: 0 the 9 at z + 1, 1 the 8 at z, 2 the 9 at z - 1), in the same order.
void gather_group(ivec3 cell, int group, GeometryWords own_geometry, inout Light dst) {
    if (group == 0) {
        [[unroll]] for (int d = 0; d < 9; ++d) add_neighbour(cell, d, own_geometry, dst);
    } else if (group == 1) {
        [[unroll]] for (int d = 9; d < 17; ++d) add_neighbour(cell, d, own_geometry, dst);
    } else {
        [[unroll]] for (int d = 17; d < 26; ++d) add_neighbour(cell, d, own_geometry, dst);
    }
}

void store(ivec3 cell, Light dst) {
    uint i = lattice_index(cell, pc.dims.xyz);
    store_light(i, stored_result(dst));
    if (pc.accumulate != 0u) accumulate_light(i, dst);
}

#include "gi/lpv/step_main.glsl"
