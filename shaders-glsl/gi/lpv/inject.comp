#version 460
// VPL injection with float atomics (see inject_vpl.glsl): fast, but the sum of a cell's VPLs
// depends on the order the threads add them in, so two runs may differ in the last bits.
#extension GL_EXT_shader_atomic_float : require
#include "gi/lpv/inject_vpl.glsl"

layout(binding = INJECT_LATTICE_R, std430) buffer LatticeR { float lattice_r[]; };
layout(binding = INJECT_LATTICE_G, std430) buffer LatticeG { float lattice_g[]; };
layout(binding = INJECT_LATTICE_B, std430) buffer LatticeB { float lattice_b[]; };

void main() {
    uint base;
    vec4 lobe;
    vec3 flux;
    if (!texel_vpl(base, lobe, flux)) return;
    for (uint k = 0u; k < 4u; ++k) {
        atomicAdd(lattice_r[base + k], lobe[k] * flux.r);
        atomicAdd(lattice_g[base + k], lobe[k] * flux.g);
        atomicAdd(lattice_b[base + k], lobe[k] * flux.b);
    }
}
