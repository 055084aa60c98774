#version 460
// The fixed-point injection's sums (inject_fixed.comp) back to float lattice coefficients:
// coefficient = sum / scale, per colour channel, overwriting the lattice (no clear needed).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RESOLVE_FIXED_R, std430) readonly buffer FixedR { int64_t fixed_r[]; };
layout(binding = RESOLVE_FIXED_G, std430) readonly buffer FixedG { int64_t fixed_g[]; };
layout(binding = RESOLVE_FIXED_B, std430) readonly buffer FixedB { int64_t fixed_b[]; };
layout(binding = RESOLVE_LATTICE_R, std430) writeonly buffer LatticeR { float lattice_r[]; };
layout(binding = RESOLVE_LATTICE_G, std430) writeonly buffer LatticeG { float lattice_g[]; };
layout(binding = RESOLVE_LATTICE_B, std430) writeonly buffer LatticeB { float lattice_b[]; };

layout(push_constant) uniform Push {
    uint coefficients; // 4 per cell
    float inverse_scale;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.coefficients) return;
    lattice_r[i] = float(fixed_r[i]) * pc.inverse_scale;
    lattice_g[i] = float(fixed_g[i]) * pc.inverse_scale;
    lattice_b[i] = float(fixed_b[i]) * pc.inverse_scale;
}
