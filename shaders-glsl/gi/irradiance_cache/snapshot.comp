#version 460
// The previous bounce's snapshot: a copy of the cache's records, taken in the round bounce.comp
// raised the flag in. One thread per record slot.
#include "gi/irradiance_cache/ic.glsl"

layout(local_size_x = IC_WORKGROUP) in;

layout(binding = IC_RECORDS, std430) readonly buffer Records { Record records[]; };
layout(binding = IC_PREVIOUS, std430) writeonly buffer Previous { Record previous[]; };
layout(binding = IC_STATE, std430) readonly buffer State { CacheState state; };

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (state.snapshot == 1u && k < state.count) previous[k] = records[k];
}
