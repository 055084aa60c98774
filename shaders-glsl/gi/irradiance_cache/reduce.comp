#version 460
// A record's irradiance, gradients and harmonic mean distance from its hemisphere (spec 003 §7,
// §10), summed on the GPU with the constant tables (src/gi/irradiance_cache/tables.rs): one
// workgroup per record this round added (workgroup y = its slot). R is then limited to
// E/|∇_t E| (the extrapolation cannot more than double or cancel E inside R) and clamped so the
// record's zone a·R spans [min, max] view pixels where it was placed; a record widened by the
// clamp has its translation gradient scaled down by as much. The f64 twins are cpu::reduce and
// cpu::limit_radius.
#include "common/sampling.glsl"
#include "gi/irradiance_cache/ic.glsl"

layout(local_size_x = IC_WORKGROUP) in;

struct Texel {
    vec4 weight_rotation;  // W, Wr.xy
    vec4 edges;            // G to the next texel along x (xy), along y (zw)
};

layout(binding = IC_HEMISPHERE, rgba32f) readonly uniform image2DArray hemisphere;
layout(binding = IC_TABLES, std430) readonly buffer Tables { Texel tables[]; };
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
        Texel table = tables[k];
        vec3 l = texel.rgb;
        float d = texel_distance(texel);
        float w = table.weight_rotation.x;
        sums[15] += w;
        if (texel.a > 0.0) sums[16] += w / d;
        for (int c = 0; c < 3; ++c) {
            sums[c] += w * l[c];
            sums[3 + 2 * c] += table.weight_rotation.y * l[c];
            sums[4 + 2 * c] += table.weight_rotation.z * l[c];
        }
        for (int e = 0; e < 2; ++e) {
            ivec2 next = xy + (e == 0 ? ivec2(1, 0) : ivec2(0, 1));
            if (next.x >= int(r) || next.y >= int(r)) continue;
            vec4 other = imageLoad(hemisphere, ivec3(next, layer));
            float nearest = min(d, texel_distance(other));
            if (isinf(nearest)) continue;
            vec2 g = e == 0 ? table.edges.xy : table.edges.zw;
            for (int c = 0; c < 3; ++c) {
                float step = (other[c] - l[c]) / nearest;
                sums[9 + 2 * c] += g.x * step;
                sums[10 + 2 * c] += g.y * step;
            }
        }
    }
    for (int s = 0; s < SUMS; ++s) partial[s][t] = sums[s];
    barrier();
    for (uint stride = IC_WORKGROUP / 2u; stride > 0u; stride >>= 1u) {
        if (t < stride) {
            for (int s = 0; s < SUMS; ++s) partial[s][t] += partial[s][t + stride];
        }
        barrier();
    }
    if (t != 0u) return;
    Record record = records[index];
    vec3 n = record.normal_footprint.xyz;
    vec3 tangent, bitangent;
    orthonormal_basis(n, tangent, bitangent);
    vec3 e = vec3(partial[0][0], partial[1][0], partial[2][0]);
    float harmonic = partial[16][0] > 0.0 ? partial[15][0] / partial[16][0] : 1.0 / 0.0;
    float gradient_limit = 1.0 / 0.0;
    for (int c = 0; c < 3; ++c) {
        vec3 rotation = tangent * partial[3 + 2 * c][0] + bitangent * partial[4 + 2 * c][0];
        vec3 translation = tangent * partial[9 + 2 * c][0] + bitangent * partial[10 + 2 * c][0];
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
