#ifndef VKGI_INJECT_VPL_GLSL
#define VKGI_INJECT_VPL_GLSL
// The VPL of one RSM texel, as both injection kernels (inject.comp with float atomics,
// inject_fixed.comp with 64-bit fixed-point atomics) place it: moved --inject-offset cells along
// its normal (default half a cell, as the thesis) or, with --inject-toward light, toward its light
// (at most half way: the segment is free, the light reached the VPL along it), and added to its
// cell as a clamped-cosine intensity lobe (Φ/π) SH_cos(n) per colour channel.
// src/gi/lpv/cpu.rs inject is the same in f64.
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/lpv/lattice.glsl"
#include "common/lights.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = INJECT_RSM_POSITION, rgba32f) readonly uniform image2DArray rsm_position;
layout(binding = INJECT_RSM_NORMAL, rgba16f) readonly uniform image2DArray rsm_normal;
layout(binding = INJECT_RSM_FLUX, rgba32f) readonly uniform image2DArray rsm_flux;
// The RSM's layers are the shadow views: their origins are the lights.
layout(binding = INJECT_VIEWS, std430) readonly buffer ShadowViews { ShadowView views[]; };

layout(push_constant) uniform Push {
    vec4 origin_cell;  // xyz lattice origin, w cell size
    ivec4 dims;        // xyz cells, w = RSM size
    uint layers;
    float offset;      // along the normal or toward the light, in cells (the thesis: 0.5)
    uint toward_light; // 1: move toward the light, 0: along the normal
    float scale;       // fixed point only: accumulator units per unit of light
} pc;

// The VPL of this invocation's texel: false if it has none (empty texel, no flux, or a cell
// outside the lattice); otherwise the index of its cell's first coefficient, its lobe and flux.
bool texel_vpl(out uint base, out vec4 lobe, out vec3 flux) {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    base = 0u;
    lobe = vec4(0.0);
    flux = vec3(0.0);
    if (texel.x >= pc.dims.w || texel.y >= pc.dims.w || uint(texel.z) >= pc.layers) return false;
    vec4 position = imageLoad(rsm_position, texel);
    flux = imageLoad(rsm_flux, texel).rgb;
    if (position.w == 0.0 || all(equal(flux, vec3(0.0)))) return false;
    vec3 n = normalize(imageLoad(rsm_normal, texel).xyz);
    float shift = pc.offset * pc.origin_cell.w;
    vec3 p;
    if (pc.toward_light != 0u) {
        vec3 to_light = views[texel.z].origin.xyz - position.xyz;
        float distance = length(to_light);
        p = position.xyz + to_light * (min(shift, 0.5 * distance) / max(distance, 1e-30));
    } else {
        p = position.xyz + n * shift;
    }
    ivec3 cell = ivec3(floor((p - pc.origin_cell.xyz) / pc.origin_cell.w));
    if (!lattice_inside(cell, pc.dims.xyz)) return false;
    base = 4u * lattice_index(cell, pc.dims.xyz);
    lobe = sh_cosine_lobe(n) * INV_PI;
    return true;
}

#endif
