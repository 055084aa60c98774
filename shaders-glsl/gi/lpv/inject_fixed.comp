#version 460
// Deterministic VPL injection (see inject_vpl.glsl): each contribution is rounded to a 64-bit
// fixed-point integer (pc.scale units per unit of light, ties to even) and added with integer
// atomics, which are associative, so a cell's sum does not depend on the order the threads run
// in: every run on the same device and driver gives the same bits. inject_resolve.comp turns
// the sums back into floats.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "gi/lpv/inject_vpl.glsl"

layout(binding = INJECT_LATTICE_R, std430) buffer FixedR { int64_t fixed_r[]; };
layout(binding = INJECT_LATTICE_G, std430) buffer FixedG { int64_t fixed_g[]; };
layout(binding = INJECT_LATTICE_B, std430) buffer FixedB { int64_t fixed_b[]; };

// 2^54, 1/512 of the accumulator's range: the scale puts a whole frame's emitted light at
// most here, so a cell's sum stays 512 times inside the range. Clamping each contribution
// to it keeps the float-to-integer conversion defined even if a light's bound were wrong.
const float MAX_UNITS = 18014398509481984.0;

int64_t units(float value) {
    return int64_t(clamp(roundEven(value * pc.scale), -MAX_UNITS, MAX_UNITS));
}

void main() {
    uint base;
    vec4 lobe;
    vec3 flux;
    if (!texel_vpl(base, lobe, flux)) return;
    for (uint k = 0u; k < 4u; ++k) {
        atomicAdd(fixed_r[base + k], units(lobe[k] * flux.r));
        atomicAdd(fixed_g[base + k], units(lobe[k] * flux.g));
        atomicAdd(fixed_b[base + k], units(lobe[k] * flux.b));
    }
}
