#version 460
// Record placement (spec 003 §17 mode B (c), mode A's one record per round): appends up to
// `batch` of this round's tile candidates, evenly spaced through them in tile order when there
// are more, as new records at their pixels' surface points. The hemisphere and reduction passes
// fill in the rest. A full cache refuses candidates and counts them (the overflow policy:
// coverage stops growing, nothing is overwritten).
#include "gi/irradiance_cache/ic.glsl"
#include "gi/irradiance_cache/draws.glsl"

layout(local_size_x = 1) in;

layout(binding = IC_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = IC_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = IC_CANDIDATES, std430) readonly buffer Candidates { uint candidates[]; };
layout(binding = IC_RECORDS, std430) buffer Records { Record records[]; };
layout(binding = IC_STATE, std430) buffer State { CacheState state; };

layout(push_constant) uniform Push {
    vec4 eye;          // xyz: the view's eye; w: world size of a pixel per unit of distance
    uvec2 size;
    uint tiles;
    uint batch;
    uint capacity;
    uint generation;   // records of another generation are gone (lights or geometry changed)
    uint scene_vertices;
} pc;

void main() {
    if (state.generation != pc.generation) empty_cache(state, pc.generation);
    uint found = 0u;
    for (uint t = 0u; t < pc.tiles; ++t) {
        if (candidates[t] != uint(IC_NONE)) ++found;
    }
    uint count = state.count;
    uint wanted = min(found, pc.batch);
    uint room = pc.capacity - min(count, pc.capacity);
    uint take = min(wanted, room);
    state.first = count;
    state.end = count + take;
    state.holes = found;
    state.overflowed += wanted - take;
    state.placed += take;
    state.added = take;
    uint seen = 0u;
    uint next = 0u;
    for (uint t = 0u; t < pc.tiles && next < take; ++t) {
        uint pixel = candidates[t];
        if (pixel == uint(IC_NONE)) continue;
        // Candidate number `seen` is taken when it is next * found / wanted (found <= tiles and
        // next < batch keep the product far below 2^32).
        if ((next * found) / wanted == seen) {
            ivec2 xy = ivec2(pixel % pc.size.x, pixel / pc.size.x);
            vec3 p = imageLoad(gbuffer_position, xy).xyz;
            vec3 n = normalize(imageLoad(gbuffer_normal, xy).xyz);
            Record r;
            r.position_harmonic = vec4(p, 0.0);
            r.normal_footprint = vec4(n, distance(p, pc.eye.xyz) * pc.eye.w);
            r.irradiance = vec4(0.0);
            for (int c = 0; c < 3; ++c) {
                r.rotation[c] = vec4(0.0);
                r.translation[c] = vec4(0.0);
            }
            records[count + next] = r;
            ++next;
        }
        ++seen;
    }
    state.count = count + take;
    write_hemisphere_draws(take, pc.batch, pc.scene_vertices);
}
