#version 460
// The fixed-point injection's sums (inject_fixed.comp) back to float lattice coefficients:
// coefficient = sum / scale, one cell (four coefficients) per thread and colour channel,
// overwriting the lattice (no clear needed).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RESOLVE_FIXED_R, std430) readonly buffer FixedR { i64vec4 fixed_r[]; };
layout(binding = RESOLVE_FIXED_G, std430) readonly buffer FixedG { i64vec4 fixed_g[]; };
layout(binding = RESOLVE_FIXED_B, std430) readonly buffer FixedB { i64vec4 fixed_b[]; };
layout(binding = RESOLVE_LATTICE_R, std430) writeonly buffer LatticeR { vec4 lattice_r[]; };
layout(binding = RESOLVE_LATTICE_G, std430) writeonly buffer LatticeG { vec4 lattice_g[]; };
layout(binding = RESOLVE_LATTICE_B, std430) writeonly buffer LatticeB { vec4 lattice_b[]; };

layout(push_constant) uniform Push {
    uint cells;
    float inverse_scale;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.cells) return;
    lattice_r[i] = vec4(fixed_r[i]) * pc.inverse_scale;
    lattice_g[i] = vec4(fixed_g[i]) * pc.inverse_scale;
    lattice_b[i] = vec4(fixed_b[i]) * pc.inverse_scale;
}
