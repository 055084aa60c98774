#version 460
// Cache-miss detection (spec 003 §8.3, §17 mode B (a)-(b)): one workgroup per tile of the view
// finds the covered pixel whose accumulated weight is below a (Eq. 8.8) and lowest, ties to the
// lowest pixel index; in scan mode (§17 mode A) one tile spans the view and the first such pixel
// in scan order wins. Writes the pixel's index, or IC_NONE, to the tile's candidate slot.
// Each subgroup finds its lanes' best with subgroup arithmetic, and the first subgroup the best
// of those behind one barrier (a tree over the workgroup in shared memory, a barrier a level,
// cost lavapipe more: docs/irradiance-cache.md).
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "gi/irradiance_cache/ic.glsl"

layout(local_size_x = IC_SELECT_WORKGROUP) in;

layout(binding = IC_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = IC_SPLAT, rgba32f) readonly uniform image2D splat;
layout(binding = IC_CANDIDATES, std430) writeonly buffer Candidates { uint candidates[]; };

layout(push_constant) uniform Push {
    uvec2 size;
    uvec2 tile;
    uint tiles_x;
    float accuracy;
    uint scan;   // 1: the first miss in scan order; 0: the least covered
} pc;

// Each subgroup's best (a workgroup has at most IC_SELECT_WORKGROUP subgroups).
shared uint shared_key[IC_SELECT_WORKGROUP];
shared uint shared_pixel[IC_SELECT_WORKGROUP];

// The subgroup's least key, ties to the lowest pixel index, as (key, pixel); IC_NONE (the
// largest index) stands for no pixel.
uvec2 subgroup_best(uint key, uint pixel) {
    uint least = subgroupMin(key);
    return uvec2(least, subgroupMin(key == least ? pixel : uint(IC_NONE)));
}

void main() {
    uint t = gl_LocalInvocationID.x;
    uvec2 origin = gl_WorkGroupID.xy * pc.tile;
    uint best_key = 0xFFFFFFFFu;
    uint best_pixel = uint(IC_NONE);
    uint pixels = pc.tile.x * pc.tile.y;
    for (uint k = t; k < pixels; k += IC_SELECT_WORKGROUP) {
        uvec2 pixel = origin + uvec2(k % pc.tile.x, k / pc.tile.x);
        if (any(greaterThanEqual(pixel, pc.size))) continue;
        if (imageLoad(gbuffer_position, ivec2(pixel)).w == 0.0) continue;
        float weight = imageLoad(splat, ivec2(pixel)).w;
        if (weight >= pc.accuracy) continue;
        uint key = pc.scan == 1u ? 0u : floatBitsToUint(max(weight, 0.0));
        uint index = pixel.y * pc.size.x + pixel.x;
        if (key < best_key || (key == best_key && index < best_pixel)) {
            best_key = key;
            best_pixel = index;
        }
    }
    uvec2 best = subgroup_best(best_key, best_pixel);
    if (subgroupElect()) {
        shared_key[gl_SubgroupID] = best.x;
        shared_pixel[gl_SubgroupID] = best.y;
    }
    barrier();
    if (gl_SubgroupID != 0u) return;
    best = uvec2(0xFFFFFFFFu, uint(IC_NONE));
    for (uint j = gl_SubgroupInvocationID; j < gl_NumSubgroups; j += gl_SubgroupSize) {
        uint key = shared_key[j];
        uint index = shared_pixel[j];
        if (key < best.x || (key == best.x && index < best.y)) best = uvec2(key, index);
    }
    best = subgroup_best(best.x, best.y);
    if (subgroupElect()) candidates[gl_WorkGroupID.y * pc.tiles_x + gl_WorkGroupID.x] = best.y;
}
