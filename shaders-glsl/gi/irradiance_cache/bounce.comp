#version 460
// Multiple bounces (Jacobi iteration over the cache): once placement has settled (no pixel left
// uncovered, or the cache is full) and the cache holds fewer bounces than asked, the cache is
// copied into the snapshot and its records are recomputed, `batch` a round, from hemispheres
// whose surfaces are lit by direct light plus the snapshot's irradiance (hemisphere.frag). This
// pass picks the round's records, [first, end) of the state, and raises the snapshot flag for
// snapshot.comp. Records placed during a refresh are shaded from the snapshot too, so they hold
// the new bounce already. Once no bounce is wanted any more it raises `done`, and the host stops
// recording the refresh until the cache is emptied. One thread.
#include "gi/irradiance_cache/ic.glsl"
#include "gi/irradiance_cache/draws.glsl"

layout(local_size_x = 1) in;

layout(binding = IC_RECORDS, std430) readonly buffer Records { Record records[]; };
layout(binding = IC_PREVIOUS, std430) readonly buffer Previous { Record previous[]; };
layout(binding = IC_STATE, std430) buffer State { CacheState state; };

layout(push_constant) uniform Push {
    uint generation;
    uint bounces;  // bounces asked for; 0: until Σ E changes by less than IC_BOUNCE_TOLERANCE
    uint batch;
    uint scene_vertices;
} pc;

// Relative change of Σ E (all channels) over the snapshot's records, from the snapshot to now.
float bounce_change() {
    float before = 0.0;
    float after = 0.0;
    for (uint k = 0u; k < state.previous_count; ++k) {
        vec3 e0 = previous[k].irradiance.rgb;
        vec3 e1 = records[k].irradiance.rgb;
        before += e0.r + e0.g + e0.b;
        after += e1.r + e1.g + e1.b;
    }
    return after > 0.0 ? abs(after - before) / after : 0.0;
}

void main() {
    if (state.generation != pc.generation) empty_cache(state, pc.generation);
    state.snapshot = 0u;
    state.first = state.count;
    state.end = state.count;
    bool refreshing = state.refreshed < state.previous_count;
    state.done = 0u;
    if (!refreshing) {
        uint target = pc.bounces == 0u ? uint(IC_MAX_BOUNCES) : min(pc.bounces, uint(IC_MAX_BOUNCES));
        bool wanted = state.bounce < target;
        if (wanted && pc.bounces == 0u && state.bounce > 1u) {
            state.change = bounce_change();
            wanted = state.change >= IC_BOUNCE_TOLERANCE;
        }
        state.done = wanted ? 0u : 1u;
        bool settled = state.count > 0u && (state.holes == 0u || state.overflowed > 0u);
        if (wanted && settled) {
            state.snapshot = 1u;
            state.previous_count = state.count;
            state.refreshed = 0u;
            state.bounce += 1u;
            refreshing = true;
        }
    }
    if (refreshing) {
        state.first = state.refreshed;
        state.end = min(state.refreshed + pc.batch, state.previous_count);
        state.refreshed = state.end;
    }
    write_hemisphere_draws(state.end - state.first, pc.batch, pc.scene_vertices);
}
