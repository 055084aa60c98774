#version 460
// Cache-miss detection (spec 003 §8.3, §17 mode B (a)-(b)): one workgroup per tile of the view
// finds the covered pixel whose accumulated weight is below a (Eq. 8.8) and lowest, ties to the
// lowest pixel index; in scan mode (§17 mode A) one tile spans the view and the first such pixel
// in scan order wins. Writes the pixel's index, or IC_NONE, to the tile's candidate slot.
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

shared uint shared_key[IC_SELECT_WORKGROUP];
shared uint shared_pixel[IC_SELECT_WORKGROUP];

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
    shared_key[t] = best_key;
    shared_pixel[t] = best_pixel;
    barrier();
    for (uint stride = IC_SELECT_WORKGROUP / 2u; stride > 0u; stride >>= 1u) {
        if (t < stride) {
            uint key = shared_key[t + stride];
            uint index = shared_pixel[t + stride];
            if (key < shared_key[t] || (key == shared_key[t] && index < shared_pixel[t])) {
                shared_key[t] = key;
                shared_pixel[t] = index;
            }
        }
        barrier();
    }
    if (t == 0u) candidates[gl_WorkGroupID.y * pc.tiles_x + gl_WorkGroupID.x] = shared_pixel[0];
}
