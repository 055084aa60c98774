#version 460
// VPL injection: every RSM texel is a VPL moved --inject-offset cells along its normal (default
// half a cell, as the thesis) or, with --inject-toward light, toward its light (at most half
// way: the segment is free, the light reached the VPL along it), and added to its cell as a
// clamped-cosine intensity lobe (Φ/π) SH_cos(n), per colour channel, with float atomics.
// src/gi/lpv/cpu.rs inject is the same in f64.
#extension GL_EXT_shader_atomic_float : require
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/lpv/lattice.glsl"
#include "common/lights.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = INJECT_RSM_POSITION, rgba32f) readonly uniform image2DArray rsm_position;
layout(binding = INJECT_RSM_NORMAL, rgba16f) readonly uniform image2DArray rsm_normal;
layout(binding = INJECT_RSM_FLUX, rgba32f) readonly uniform image2DArray rsm_flux;
layout(binding = INJECT_LATTICE_R, std430) buffer LatticeR { float lattice_r[]; };
layout(binding = INJECT_LATTICE_G, std430) buffer LatticeG { float lattice_g[]; };
layout(binding = INJECT_LATTICE_B, std430) buffer LatticeB { float lattice_b[]; };
// The RSM's layers are the shadow views: their origins are the lights.
layout(binding = INJECT_VIEWS, std430) readonly buffer ShadowViews { ShadowView views[]; };

layout(push_constant) uniform Push {
    vec4 origin_cell;  // xyz lattice origin, w cell size
    ivec4 dims;        // xyz cells, w = RSM size
    uint layers;
    float offset;      // along the normal or toward the light, in cells (the thesis: 0.5)
    uint toward_light; // 1: move toward the light, 0: along the normal
} pc;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (texel.x >= pc.dims.w || texel.y >= pc.dims.w || uint(texel.z) >= pc.layers) return;
    vec4 position = imageLoad(rsm_position, texel);
    vec3 flux = imageLoad(rsm_flux, texel).rgb;
    if (position.w == 0.0 || all(equal(flux, vec3(0.0)))) return;
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
    if (!lattice_inside(cell, pc.dims.xyz)) return;
    uint base = 4u * lattice_index(cell, pc.dims.xyz);
    vec4 lobe = sh_cosine_lobe(n) * INV_PI;
    for (uint k = 0u; k < 4u; ++k) {
        atomicAdd(lattice_r[base + k], lobe[k] * flux.r);
        atomicAdd(lattice_g[base + k], lobe[k] * flux.g);
        atomicAdd(lattice_b[base + k], lobe[k] * flux.b);
    }
}
