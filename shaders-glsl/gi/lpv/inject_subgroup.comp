#version 460
// VPL injection with float atomics (inject.comp), the VPLs of a subgroup summed per cell first:
// neighbouring RSM texels mostly fall in one cell, so only the first lane of each cell adds its
// cell's sum. Every lane visits the subgroup's lanes in turn (shuffles) and sums those in its
// cell: for the narrow subgroups of a CPU device (SUBGROUP_LANES, at most 16), where each float
// atomic is a compare-and-swap loop per lane and the lanes are few. It reads every lane, so the
// workgroups must be whole subgroups (src/gi/lpv/technique.rs chooses it only where the subgroup
// size divides the workgroup's). The sums' order differs from inject.comp's, which already
// depends on the threads' order.
#extension GL_EXT_shader_atomic_float : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_control_flow_attributes : require
#include "gi/lpv/inject_vpl.glsl"

layout(binding = INJECT_LATTICE_R, std430) buffer LatticeR { float lattice_r[]; };
layout(binding = INJECT_LATTICE_G, std430) buffer LatticeG { float lattice_g[]; };
layout(binding = INJECT_LATTICE_B, std430) buffer LatticeB { float lattice_b[]; };

// The device's subgroup size (the loop over the lanes unrolls to it).
layout(constant_id = 0) const uint SUBGROUP_LANES = 8u;

void main() {
    uint base;
    vec4 lobe;
    vec3 flux;
    bool has_vpl = texel_vpl(base, lobe, flux);
    // A lane without a VPL has no cell (and a zero lobe).
    uint cell = has_vpl ? base : 0xffffffffu;
    vec4 r = vec4(0.0);
    vec4 g = vec4(0.0);
    vec4 b = vec4(0.0);
    bool first_in_cell = has_vpl;
    [[unroll]] for (uint lane = 0u; lane < SUBGROUP_LANES; ++lane) {
        if (lane < gl_SubgroupSize) {
            bool same = subgroupShuffle(cell, lane) == cell;
            vec4 lane_r = subgroupShuffle(lobe * flux.r, lane);
            vec4 lane_g = subgroupShuffle(lobe * flux.g, lane);
            vec4 lane_b = subgroupShuffle(lobe * flux.b, lane);
            if (same) {
                r += lane_r;
                g += lane_g;
                b += lane_b;
                if (lane < gl_SubgroupInvocationID) first_in_cell = false;
            }
        }
    }
    if (first_in_cell) {
        for (uint k = 0u; k < 4u; ++k) {
            atomicAdd(lattice_r[base + k], r[k]);
            atomicAdd(lattice_g[base + k], g[k]);
            atomicAdd(lattice_b[base + k], b[k]);
        }
    }
}
