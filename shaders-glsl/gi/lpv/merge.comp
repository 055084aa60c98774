#version 460
// The ILPV blend (seed 000 eq. 3.4) for one colour channel, in place:
// current = current * (1 - λ_incr) + previous * λ_incr * E_now / E_before. A previous factor of
// 0 means nothing is carried (the first frame): the previous lattice is then not read.
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = MERGE_CURRENT, std430) buffer Current { vec4 current_cells[]; };
layout(binding = MERGE_PREVIOUS, std430) readonly buffer Previous { vec4 previous_cells[]; };

layout(push_constant) uniform Push {
    uint cells;
    float previous_factor;
    float current_factor;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.cells) return;
    vec4 carried = pc.previous_factor > 0.0 ? previous_cells[i] * pc.previous_factor : vec4(0.0);
    current_cells[i] = current_cells[i] * pc.current_factor + carried;
}
