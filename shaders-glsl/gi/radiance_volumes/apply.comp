#version 460
#extension GL_EXT_control_flow_attributes : require
// Cache apply (spec 001 §4.5): each lit pixel's irradiance interpolated trilinearly from the 8
// corner caches of its cell, each cache's SH irradiance at the pixel's normal clamped to zero
// first, blended with the next cascade near a decision box's face, and added to the view's HDR
// image as albedo / pi · E. Corners without a cache are counted (the allocation invariant says
// none are); corners refused for a full cache buffer are left out and the weights renormalised.
// Glossy pixels (indirect specular on) also sum the corner caches' hemisphere maps, with the
// same weights, under their GGX lobe, each map in its own cache's frame:
// specular · G1(n·v) / (4 n·v) · Σ_k T_k ⟨D(n·h) G1(n·l(h))⟩_k ΔΩ (specular.rs explains it).
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
// The caches read as texels: lavapipe reads a storage buffer at an index that differs across
// lanes lane by lane, in a loop with a branch a lane (this pass took 40% longer so).
layout(binding = RV_CACHES) uniform samplerBuffer caches;
layout(binding = RV_SPECULAR, std430) readonly buffer Specular { vec4 specular[]; };
layout(binding = RV_STATE, std430) buffer State { RvState state; };

layout(push_constant) uniform Push {
    vec4 eye_side;      // the cascades' centre, the first cascade's side
    uvec2 size;
    uint cascade_count;
    uint resolution;
    float transition;
    uint stride;
    uint specular_side; // side of a cache's hemisphere map (0: no indirect specular)
    uint specular_texels;
} pc;

// What the settings switch on, fixed when the pipeline is built (passes.rs): lavapipe runs
// every branch for every pixel, and a loop bounded by a push constant indexes its arrays lane by
// lane. COEFFICIENTS: the caches' SH coefficients (4 or 9); SPECULAR: indirect specular on;
// FRONT_ONLY: corners behind the pixel's surface left out.
layout(constant_id = 0) const uint COEFFICIENTS = 4u;
layout(constant_id = 1) const bool SPECULAR = false;
layout(constant_id = 2) const bool FRONT_ONLY = false;

// The caches a glossy pixel blends the maps of, with their weights (both cascades' corners).
uint map_cache[16];
float map_weight[16];
uint map_count = 0u;

RvGrid grid() {
    return RvGrid(pc.eye_side.xyz, pc.eye_side.w, pc.cascade_count, pc.resolution, pc.transition);
}

vec3 cache_irradiance(uint index, vec3 n) {
    float y[SH_L2_COEFFICIENTS];
    sh_l2_basis(n, y);
    vec3 e = vec3(0.0);
    [[unroll]] for (uint i = 0u; i < COEFFICIENTS; ++i) {
        e += texelFetch(caches, int(index * pc.stride + 1u + i)).rgb * (sh_cosine_convolution(i) * y[i]);
    }
    return max(e, vec3(0.0));
}

// The irradiance interpolated from cascade `cascade`; with `maps`, the same corner caches and
// their normalised weights times `share` go to the map list.
vec3 interpolate(uint cascade, vec3 p, vec3 n, bool maps, float share, inout uint missing) {
    uint first = map_count;
    uvec3 g;
    vec3 f;
    rv_cell(grid(), cascade, p, g, f);
    Cascade c = rv_cascade(grid(), cascade);
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
        uvec3 corner = uvec3(k & 1u, (k >> 1) & 1u, k >> 2);
        vec3 axis = mix(1.0 - f, f, vec3(corner));
        float w = axis.x * axis.y * axis.z;
        if (FRONT_ONLY) {
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
        if (maps) {
            map_cache[map_count] = value - 1u;
            map_weight[map_count] = w;
            map_count += 1u;
        }
    }
    if (weights > 0.0) {
        for (uint i = first; i < map_count; ++i) map_weight[i] *= share / weights;
    } else {
        map_count = first;
    }
    return weights > 0.0 ? sum / weights : vec3(0.0);
}

// D(n·h) G1(n·l(h)) for D of width² d2 and shadowing of width² a2 around local n, l(h)
// reflecting the eye (local z); 0 where h or l is below the surface.
float lobe_weight(vec3 n, vec3 h, float d2, float a2) {
    float n_h = dot(n, h);
    float n_l = dot(n, h * (2.0 * h.z) - vec3(0.0, 0.0, 1.0));
    return n_h > 0.0 && n_l > 0.0 ? ggx_d(n_h, d2) * smith_g1(n_l, a2) : 0.0;
}

// The corner caches' maps, weighted, under the GGX lobe of width alpha around the world normal
// n, each map in its own cache's frame, texel by texel; near a narrow lobe's axis at several
// points a texel (specular.rs `under_lobe`).
vec3 under_lobe(vec3 n_world, float alpha) {
    uint side = pc.specular_side;
    float a2 = alpha * alpha;
    float d_alpha = rv_sampled_alpha(alpha, side);
    float d2 = d_alpha * d_alpha;
    uint samples = rv_texel_samples(d_alpha, side);
    float near = rv_near_cosine(d_alpha, side);
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < map_count; ++i) {
        uint cache = map_cache[i];
        vec3 to_eye = pc.eye_side.xyz - texelFetch(caches, int(cache * pc.stride)).xyz;
        vec3 n = rv_local(n_world, dot(to_eye, to_eye) > 0.0 ? normalize(to_eye) : vec3(0.0, 0.0, 1.0));
        vec3 part = vec3(0.0);
        for (uint k = 0u; k < side * side; ++k) {
            vec3 centre = rv_texel_centre(k, side);
            float w = 0.0;
            if (samples > 1u && dot(n, centre) > near) {
                vec2 corner = vec2(k % side, k / side);
                for (uint y = 0u; y < samples; ++y) {
                    for (uint x = 0u; x < samples; ++x) {
                        vec2 uv = (corner + (vec2(x, y) + 0.5) / float(samples)) / float(side);
                        w += lobe_weight(n, rv_hemisphere_unmap(uv), d2, a2);
                    }
                }
                w /= float(samples * samples);
            } else {
                w = lobe_weight(n, centre, d2, a2);
            }
            if (w > 0.0) part += w * specular[cache * pc.specular_texels + k].rgb;
        }
        sum += map_weight[i] * part;
    }
    return sum * (2.0 * PI / float(side * side));
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
    vec3 v = pc.eye_side.xyz - position.xyz;
    v = dot(v, v) > 0.0 ? normalize(v) : n;
    float n_v = dot(n, v);
    bool maps = SPECULAR && any(greaterThan(gloss.rgb, vec3(0.0))) && n_v > 0.0;
    uint missing = 0u;
    // The serving cascade, then, for a pixel near its decision box's face, the next one: in a
    // loop, not an `if`, since lavapipe runs both sides of an `if` for every pixel but leaves a
    // loop once none of a batch's pixels goes on, so a batch with no pixel near a face
    // interpolates one cascade.
    vec3 served = vec3(0.0);
    vec3 next = vec3(0.0);
    for (uint round = 0u; round < 2u; ++round) {
        vec3 e = interpolate(cascade + round, position.xyz, n, maps, round == 0u ? 1.0 - blend : blend,
                             missing);
        if (round == 0u) served = e;
        else next = e;
        if (!(blend > 0.0)) break;
    }
    vec3 e = blend > 0.0 ? mix(served, next, blend) : served;
    if (missing > 0u) atomicAdd(state.missing, missing);
    vec3 radiance = imageLoad(gbuffer_albedo, pixel).rgb * INV_PI * e;
    if (maps) {
        float alpha = gloss.a * gloss.a;
        float g1 = smith_g1(n_v, alpha * alpha);
        radiance += gloss.rgb * (g1 / (4.0 * n_v)) * under_lobe(n, alpha);
    }
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
