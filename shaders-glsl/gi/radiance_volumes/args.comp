#version 460
// The lighting pass's indirect dispatch (spec 001 §4.2 step 5): one thread per cache held.
#include "gi/radiance_volumes/state.glsl"

layout(local_size_x = 1) in;

layout(binding = RV_STATE, std430) buffer State { RvState state; };

layout(push_constant) uniform Push {
    uint capacity;
} pc;

void main() {
    uint held = min(state.requested, pc.capacity);
    state.groups_x = (held + RV_LIGHT_GROUP - 1u) / RV_LIGHT_GROUP;
    state.groups_y = 1u;
    state.groups_z = 1u;
}
