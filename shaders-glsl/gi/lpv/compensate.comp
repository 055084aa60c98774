#version 460
// Clamp compensation for the 26-neighbour step (one colour channel, in place): apply the step's
// medium to each cell (absorption from both bands, isotropic scattering moves the directional
// band's scattered part into the DC band) and scale it so that one unblocked step, then pure
// transport, moves exactly the energy the medium left: by E over the energy the clamped
// transfers would move. src/gi/lpv/cpu.rs medium_mix and compensate_clamp in f64.
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
    float keep_dc;           // 1 - λa
    float keep_directional;  // 1 - λa - λs
} pc;

void main() {
    // No early return: with the rest under a branch, lavapipe took 2.7x this pass's time to read
    // the neighbours' uniform buffer and sum (docs/performance.md). An invocation past the
    // end computes the last cell again (reading it while its own invocation may write it; the
    // value is discarded) and stores nothing.
    uint i = min(gl_GlobalInvocationID.x, pc.count - 1u);
    vec4 l = cells[i] * vec4(pc.keep_dc, vec3(pc.keep_directional));
    float moved = 0.0;
    [[unroll]] for (int d = 0; d < 26; ++d) {
        moved += max(dot(l, neighbours[d].transfer), 0.0) * neighbours[d].transfer.x;
    }
    vec4 compensated = moved > 0.0 && l.x > 0.0 ? l * (l.x / moved) : l;
    if (gl_GlobalInvocationID.x < pc.count) cells[i] = compensated;
}
