#version 460
// Cache apply (spec 001 §4.5): each lit pixel's irradiance interpolated trilinearly from the 8
// corner caches of its cell, each cache's SH irradiance at the pixel's normal clamped to zero
// first, blended with the next cascade near a decision box's face, and added to the view's HDR
// image as albedo / pi · E. Corners without a cache are counted (the allocation invariant says
// none are); corners refused for a full cache buffer are left out and the weights renormalised.
// Glossy pixels (indirect specular on) also read each corner cache's hemisphere map at their
// normal, in the frame of the pixel toward the eye, filtered at the roughness's mip level, with
// the same weights, and add specular · G1(n·v)² / (4 n·v) times it (specular.rs explains why).
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "gi/shared/sh.glsl"
#include "gi/radiance_volumes/specular.glsl"
#include "gi/radiance_volumes/rv.glsl"
#include "gi/radiance_volumes/state.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = RV_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = RV_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = RV_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = RV_GBUFFER_SPECULAR, rgba16f) readonly uniform image2D gbuffer_specular;
layout(binding = RV_HDR, rgba32f) uniform image2D hdr;
layout(binding = RV_ADDRESS, std430) readonly buffer Address { uint address[]; };
layout(binding = RV_CACHES, std430) readonly buffer Caches { vec4 caches[]; };
layout(binding = RV_SPECULAR, std430) readonly buffer Specular { vec4 specular[]; };
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
    uint specular_side; // side of a cache's hemisphere map (0: no indirect specular)
    uint specular_texels;
} pc;

// Where and how finely a glossy pixel reads the maps (uv < 0: it reads none).
struct MapRead {
    vec2 uv;
    float lod;
};

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

// Level `level` of cache `index`'s map at uv, bilinear between the texel centres.
vec3 map_level(uint index, uint level, vec2 uv) {
    uint s = pc.specular_side >> level;
    uint first = index * pc.specular_texels + rv_specular_level_offset(pc.specular_side, level);
    vec2 at = clamp(uv * float(s) - 0.5, vec2(0.0), vec2(float(s - 1u)));
    uvec2 lo = uvec2(floor(at));
    vec2 f = at - vec2(lo);
    uvec2 hi = min(lo + 1u, uvec2(s - 1u));
    vec3 a = mix(specular[first + lo.y * s + lo.x].rgb, specular[first + lo.y * s + hi.x].rgb, f.x);
    vec3 b = mix(specular[first + hi.y * s + lo.x].rgb, specular[first + hi.y * s + hi.x].rgb, f.x);
    return mix(a, b, f.y);
}

// Cache `index`'s map at uv, trilinear at lod.
vec3 map_sample(uint index, MapRead read) {
    uint below = uint(floor(read.lod));
    float f = read.lod - float(below);
    vec3 lower = map_level(index, below, read.uv);
    return f > 0.0 ? mix(lower, map_level(index, below + 1u, read.uv), f) : lower;
}

// The irradiance (and in `glossy`, the filtered map) interpolated from cascade `cascade`.
vec3 interpolate(uint cascade, vec3 p, vec3 n, MapRead read, out vec3 glossy, inout uint missing) {
    glossy = vec3(0.0);
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
        if (read.uv.x >= 0.0) glossy += w * map_sample(value - 1u, read);
        weights += w;
    }
    if (weights > 0.0) glossy /= weights;
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
    // A glossy pixel facing the eye reads the maps at its normal in its own frame.
    vec4 gloss = imageLoad(gbuffer_specular, pixel);
    MapRead read = MapRead(vec2(-1.0), 0.0);
    float lobe = 0.0;
    vec3 v = pc.eye_side.xyz - position.xyz;
    if (pc.specular_side > 0u && any(greaterThan(gloss.rgb, vec3(0.0))) && dot(v, v) > 0.0) {
        v = normalize(v);
        float n_v = dot(n, v);
        if (n_v > 0.0) {
            float a = gloss.a * gloss.a;
            float g1 = smith_g1(n_v, a * a);
            lobe = g1 * g1 / (4.0 * n_v);
            read = MapRead(rv_hemisphere_map(rv_local(n, v)), rv_specular_lod(pc.specular_side, gloss.a));
        }
    }
    uint missing = 0u;
    vec3 glossy;
    vec3 e = interpolate(cascade, position.xyz, n, read, glossy, missing);
    if (blend > 0.0) {
        vec3 next_glossy;
        e = mix(e, interpolate(cascade + 1u, position.xyz, n, read, next_glossy, missing), blend);
        glossy = mix(glossy, next_glossy, blend);
    }
    if (missing > 0u) atomicAdd(state.missing, missing);
    vec3 radiance = imageLoad(gbuffer_albedo, pixel).rgb * INV_PI * e + gloss.rgb * lobe * glossy;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
