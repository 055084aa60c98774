#version 460
// Clamp compensation for the 26-neighbour step (one colour channel, in place): scale each cell
// so that one unblocked, lossless step moves exactly its energy, by E_in over the energy the
// clamped transfers would move. src/gi/lpv/cpu.rs compensate_clamp is the same in f64.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = LINEAR_WORKGROUP) in;

struct Neighbour {
    vec4 transfer;
    ivec3 offset;
    float outscatter;
};

layout(binding = COMPENSATE_CELLS, std430) buffer Cells { vec4 cells[]; };
layout(binding = COMPENSATE_NEIGHBOURS, std140) uniform Neighbours { Neighbour neighbours[26]; };

layout(push_constant) uniform Push {
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 l = cells[i];
    float moved = 0.0;
    [[unroll]] for (int d = 0; d < 26; ++d) {
        moved += max(dot(l, neighbours[d].transfer), 0.0) * neighbours[d].transfer.x;
    }
    if (moved > 0.0 && l.x > 0.0) cells[i] = l * (l.x / moved);
}
