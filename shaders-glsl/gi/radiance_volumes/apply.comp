#version 460
// Cache apply (spec 001 §4.5): each lit pixel's irradiance interpolated trilinearly from the 8
// corner caches of its cell, each cache's SH irradiance at the pixel's normal clamped to zero
// first, blended with the next cascade near a decision box's face, and added to the view's HDR
// image as albedo / pi · E. Corners without a cache are counted (the allocation invariant says
// none are); corners refused for a full cache buffer are left out and the weights renormalised.
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/radiance_volumes/rv.glsl"
#include "gi/radiance_volumes/state.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = RV_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = RV_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = RV_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = RV_HDR, rgba32f) uniform image2D hdr;
layout(binding = RV_ADDRESS, std430) readonly buffer Address { uint address[]; };
layout(binding = RV_CACHES, std430) readonly buffer Caches { vec4 caches[]; };
layout(binding = RV_STATE, std430) buffer State { RvState state; };

layout(push_constant) uniform Push {
    vec4 eye_side;      // the cascades' centre, the first cascade's side
    uvec2 size;
    uint cascade_count;
    uint resolution;
    float transition;
    uint stride;
    uint coefficients;
    uint front_only;    // leave out corners behind the pixel's surface
} pc;

RvGrid grid() {
    return RvGrid(pc.eye_side.xyz, pc.eye_side.w, pc.cascade_count, pc.resolution, pc.transition);
}

vec3 cache_irradiance(uint index, vec3 n) {
    float y[SH_L2_COEFFICIENTS];
    sh_l2_basis(n, y);
    vec3 e = vec3(0.0);
    for (uint i = 0u; i < pc.coefficients; ++i) {
        e += caches[index * pc.stride + 1u + i].rgb * (sh_cosine_convolution(i) * y[i]);
    }
    return max(e, vec3(0.0));
}

vec3 interpolate(uint cascade, vec3 p, vec3 n, inout uint missing) {
    uvec3 g;
    vec3 f;
    rv_cell(grid(), cascade, p, g, f);
    Cascade c = rv_cascade(grid(), cascade);
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    for (uint k = 0u; k < 8u; ++k) {
        uvec3 corner = uvec3(k & 1u, (k >> 1) & 1u, k >> 2);
        vec3 axis = mix(1.0 - f, f, vec3(corner));
        float w = axis.x * axis.y * axis.z;
        if (pc.front_only != 0u) {
            // A corner behind the pixel's surface may lie inside the object or beyond the wall
            // it belongs to: it is left out (its light would leak or be shadowed by that
            // surface).
            vec3 at = c.lo + vec3(g + corner) * c.cell;
            if (dot(at - p, n) < -1e-3 * c.cell) continue;
        }
        uint value = address[rv_corner_index(cascade, g + corner, pc.resolution)];
        if (value == RV_EMPTY || value == RV_LOCKED) {
            missing += 1u;
            continue;
        }
        if (value == RV_REFUSED) continue;
        sum += w * cache_irradiance(value - 1u, n);
        weights += w;
    }
    return weights > 0.0 ? sum / weights : vec3(0.0);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0) return;
    float blend;
    uint cascade = rv_select(grid(), position.xyz, blend);
    if (cascade == RV_NONE) {
        atomicAdd(state.beyond, 1u);
        return;
    }
    vec3 stored = imageLoad(gbuffer_normal, pixel).xyz;
    if (!(dot(stored, stored) > 0.0)) return;
    vec3 n = normalize(stored);
    uint missing = 0u;
    vec3 e = interpolate(cascade, position.xyz, n, missing);
    if (blend > 0.0) e = mix(e, interpolate(cascade + 1u, position.xyz, n, missing), blend);
    if (missing > 0u) atomicAdd(state.missing, missing);
    vec3 radiance = imageLoad(gbuffer_albedo, pixel).rgb * INV_PI * e;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
