// One classic LPV step for one colour channel, or all three (CHANNELS, cells.glsl) (Kaplanyan &
// Dachsbacher 2010): from each of the 6 face neighbours, the flux through the 5 faces of this
// cell other than the shared one (Ω_f times the source's intensity toward the face centre),
// re-emitted as a cosine lobe around the face normal; the step's result is also added to the accumulation lattice. Blocking
// (blocking.glsl): the thesis's SH lobes use the mean geometry of source and destination (the
// shared face, as KD10's half-cell-offset geometry volume); the projected-area models the
// source's, like ILPV: light crosses a wall in the cell that holds it, a one-way wall blocks
// light leaving through it and not light on its way to it; visibility the segment between the
// two centres. src/gi/lpv/cpu.rs step_6 is the same in f64.
// Included by lpv/lpv_{tiled,naive,column}{,_rgb}.comp.

#extension GL_EXT_control_flow_attributes : require
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

struct Face {
    vec4 evaluation;  // Ω_f times the SH basis at the direction of the face centre
    vec4 lobe;        // SH_cos(face normal) / pi
};

struct Axis {
    ivec4 offset;             // xyz = direction from source to this cell
    vec4 blocking_transfer;   // the 26-neighbour transfer vector of this direction
    Face faces[5];
};

layout(binding = STEP_CONSTANTS, std140) uniform Axes { Axis axes[6]; };

layout(push_constant) uniform Push {
    ivec4 dims;
} pc;

#include "gi/lpv/tile.glsl"

// The axes' constants, read by load_step_constants() at the top of main, outside every branch
// and loop: read where they are used, inside the column's loop, they cost lavapipe twice this
// step's time (docs/performance.md).
vec4 axis_blocking_transfer[6];
vec4 face_evaluation[6 * 5];
vec4 face_lobe[6 * 5];

void load_step_constants() {
    [[unroll]] for (int a = 0; a < 6; ++a) {
        axis_blocking_transfer[a] = axes[a].blocking_transfer;
        [[unroll]] for (int f = 0; f < 5; ++f) {
            face_evaluation[a * 5 + f] = axes[a].faces[f].evaluation;
            face_lobe[a * 5 + f] = axes[a].faces[f].lobe;
        }
    }
}

// The a-th axis, from source to this cell: +x, -x, +y, -y, +z, -z (transfer.rs FaceScheme;
// axes[a].offset holds the same), a constant once the loop is unrolled.
ivec3 axis_offset(int a) {
    ivec3 unit = ivec3(a / 2 == 0 ? 1 : 0, a / 2 == 1 ? 1 : 0, a / 2 == 2 ? 1 : 0);
    return a % 2 == 0 ? unit : -unit;
}

// The light `cell` gathers through its faces from its 6 face neighbours, in every channel the
// step carries (the blocking, which depends on the geometry alone, once for all of them).
Light gather(ivec3 cell) {
    GeometryWords own_geometry = source_geometry(cell, ivec3(0));
    Light dst = no_light();
    [[unroll]] for (int a = 0; a < 6; ++a) {
        ivec3 offset = axis_offset(a);
        GeometryWords source = source_geometry(cell, -offset);
        GeometryWords blocker = source;
        if (GEOMETRY_WORDS == 1u) blocker = mean_geometry(source, own_geometry);
        float blocked = blocking_of(blocker, own_geometry, axis_blocking_transfer[a], offset);
        float blocking = passing_share(blocked);
        [[unroll]] for (int c = 0; c < CHANNELS; ++c) {
            vec4 src = source_light(cell, -offset, c);
            [[unroll]] for (int f = 0; f < 5; ++f) {
                float flux = max(dot(src, face_evaluation[a * 5 + f]), 0.0) * blocking;
                dst.c[c] += face_lobe[a * 5 + f] * flux;
            }
        }
    }
    return dst;
}

void store(ivec3 cell, Light dst) {
    uint i = lattice_index(cell, pc.dims.xyz);
    store_light(i, dst);
    accumulate_light(i, dst);
}

#include "gi/lpv/step_main.glsl"
