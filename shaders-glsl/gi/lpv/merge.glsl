// The ILPV blend (seed 000 eq. 3.4) of the colour channels of one part (CHANNELS 1: one
// channel, at the _R bindings; 3: R, G and B in one dispatch) into a target lattice:
// target = current * current_factor + previous * previous_factor, per channel. The target is
// the current lattice itself (this frame's injection blended in place: E_now / E_before scales
// the carried light) or another lattice (a far field's accumulation, started from both). A
// previous factor of 0 means nothing is carried (the first frame): the previous lattice is then
// not read. Included by lpv/merge{,_rgb}.comp.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = LINEAR_WORKGROUP) in;

#define MERGED(target_binding, current_binding, previous_binding, c)                          \
    layout(binding = target_binding, std430) writeonly buffer Target##c { vec4 target_##c[]; };  \
    layout(binding = current_binding, std430) readonly buffer Current##c { vec4 current_##c[]; }; \
    layout(binding = previous_binding, std430) readonly buffer Previous##c { vec4 previous_##c[]; };
MERGED(MERGE_TARGET_R, MERGE_CURRENT_R, MERGE_PREVIOUS_R, r)
#if CHANNELS == 3
MERGED(MERGE_TARGET_G, MERGE_CURRENT_G, MERGE_PREVIOUS_G, g)
MERGED(MERGE_TARGET_B, MERGE_CURRENT_B, MERGE_PREVIOUS_B, b)
#endif

layout(push_constant) uniform Push {
    vec4 previous_factor;  // per channel (x: R or the one channel, y: G, z: B)
    vec4 current_factor;
    uint cells;
} pc;

// One channel's cell blended: this frame's `current`, last frame's `previous`, channel `c`'s
// factors.
vec4 blended(vec4 current, vec4 previous, int c) {
    float previous_factor = pc.previous_factor[c];
    vec4 carried = previous_factor > 0.0 ? previous * previous_factor : vec4(0.0);
    return current * pc.current_factor[c] + carried;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.cells) return;
    target_r[i] = blended(current_r[i], previous_r[i], 0);
#if CHANNELS == 3
    target_g[i] = blended(current_g[i], previous_g[i], 1);
    target_b[i] = blended(current_b[i], previous_b[i], 2);
#endif
}
