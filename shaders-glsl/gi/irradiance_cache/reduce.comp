#version 460
// A record's irradiance, gradients and harmonic mean distance from its hemisphere (spec 003 §7,
// §10), summed on the GPU with the constant tables (src/gi/irradiance_cache/tables.rs): one
// workgroup per record this round added (workgroup y = its slot). R is then limited to
// E/|∇_t E| (the extrapolation cannot more than double or cancel E inside R) and clamped so the
// record's zone a·R spans [min, max] view pixels where it was placed; a record widened by the
// clamp has its translation gradient scaled down by as much. The f64 twins are cpu::reduce and
// cpu::limit_radius.
//
// The workgroup's lanes sum with subgroup arithmetic and then across the subgroups through
// shared memory behind one barrier: a tree over the workgroup in shared memory took two thirds
// of the pass on lavapipe (which reads shared memory lane by lane at a lane's index and pays
// each barrier), docs/irradiance-cache.md.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "common/sampling.glsl"
#include "gi/irradiance_cache/ic.glsl"

layout(local_size_x = IC_WORKGROUP) in;

layout(binding = IC_HEMISPHERE, rgba32f) readonly uniform image2DArray hemisphere;
// Two texels a hemisphere texel: (W, Wr.xy, 0), then G to the next texel along x (xy) and
// along y (zw). Texel fetches, which lavapipe makes for all the lanes of a SIMD batch at once
// (a storage buffer at the loop's index it reads lane by lane).
layout(binding = IC_TABLES) uniform samplerBuffer tables;
layout(binding = IC_RECORDS, std430) buffer Records { Record records[]; };
layout(binding = IC_STATE, std430) readonly buffer State { CacheState state; };

layout(push_constant) uniform Push {
    uint resolution;
    float accuracy;
    float min_zone_pixels;
    float max_zone_pixels;
} pc;

// E (3), ∇_r (6), ∇_t (6), Σ W, Σ W / d.
#define SUMS 17
// Each subgroup's sums (a workgroup has at most IC_WORKGROUP subgroups).
shared float partial[SUMS][IC_WORKGROUP];

// Distance of a texel's surface; a texel that saw nothing is infinitely far.
float texel_distance(vec4 texel) {
    return texel.a > 0.0 ? texel.a : 1.0 / 0.0;
}

void main() {
    uint index = state.first + gl_WorkGroupID.y;
    if (index >= state.end) return;
    uint t = gl_LocalInvocationID.x;
    uint r = pc.resolution;
    int layer = int(gl_WorkGroupID.y);
    float sums[SUMS];
    for (int s = 0; s < SUMS; ++s) sums[s] = 0.0;
    for (uint k = t; k < r * r; k += IC_WORKGROUP) {
        ivec2 xy = ivec2(k % r, k / r);
        vec4 texel = imageLoad(hemisphere, ivec3(xy, layer));
        vec4 weight_rotation = texelFetch(tables, int(2u * k));
        vec4 edges = texelFetch(tables, int(2u * k + 1u));
        vec3 l = texel.rgb;
        float d = texel_distance(texel);
        float w = weight_rotation.x;
        sums[15] += w;
        if (texel.a > 0.0) sums[16] += w / d;
        for (int c = 0; c < 3; ++c) {
            sums[c] += w * l[c];
            sums[3 + 2 * c] += weight_rotation.y * l[c];
            sums[4 + 2 * c] += weight_rotation.z * l[c];
        }
        for (int e = 0; e < 2; ++e) {
            ivec2 next = xy + (e == 0 ? ivec2(1, 0) : ivec2(0, 1));
            if (next.x >= int(r) || next.y >= int(r)) continue;
            vec4 other = imageLoad(hemisphere, ivec3(next, layer));
            float nearest = min(d, texel_distance(other));
            if (isinf(nearest)) continue;
            vec2 g = e == 0 ? edges.xy : edges.zw;
            for (int c = 0; c < 3; ++c) {
                float step = (other[c] - l[c]) / nearest;
                sums[9 + 2 * c] += g.x * step;
                sums[10 + 2 * c] += g.y * step;
            }
        }
    }
    for (int s = 0; s < SUMS; ++s) sums[s] = subgroupAdd(sums[s]);
    if (subgroupElect()) {
        for (int s = 0; s < SUMS; ++s) partial[s][gl_SubgroupID] = sums[s];
    }
    barrier();
    // The first subgroup sums the subgroups' sums; its first lane writes the record.
    if (gl_SubgroupID != 0u) return;
    for (int s = 0; s < SUMS; ++s) {
        float sum = 0.0;
        for (uint j = gl_SubgroupInvocationID; j < gl_NumSubgroups; j += gl_SubgroupSize) {
            sum += partial[s][j];
        }
        sums[s] = subgroupAdd(sum);
    }
    if (!subgroupElect()) return;
    Record record = records[index];
    vec3 n = record.normal_footprint.xyz;
    vec3 tangent, bitangent;
    orthonormal_basis(n, tangent, bitangent);
    vec3 e = vec3(sums[0], sums[1], sums[2]);
    float harmonic = sums[16] > 0.0 ? sums[15] / sums[16] : 1.0 / 0.0;
    float gradient_limit = 1.0 / 0.0;
    for (int c = 0; c < 3; ++c) {
        vec3 rotation = tangent * sums[3 + 2 * c] + bitangent * sums[4 + 2 * c];
        vec3 translation = tangent * sums[9 + 2 * c] + bitangent * sums[10 + 2 * c];
        record.rotation[c] = vec4(rotation, 0.0);
        record.translation[c] = vec4(translation, 0.0);
        float slope = length(translation);
        if (slope > 0.0 && e[c] > 0.0) gradient_limit = min(gradient_limit, e[c] / slope);
    }
    float pixel = record.normal_footprint.w;
    float smallest = pc.min_zone_pixels * pixel / pc.accuracy;
    float largest = pc.max_zone_pixels * pixel / pc.accuracy;
    float limited = min(harmonic, gradient_limit);
    float radius = clamp(limited, smallest, largest);
    // A record widened past its limits extrapolates with its gradient scaled down as much
    // (Křivánek et al. 2006), so E' changes by at most E over the zone.
    if (radius > limited) {
        for (int c = 0; c < 3; ++c) record.translation[c] *= limited / radius;
    }
    record.position_harmonic.w = radius;
    record.irradiance = vec4(e, 0.0);
    records[index] = record;
}
