#version 460
// Cache lighting (spec 001 §4.4, §4.6): one thread per cache held, dispatched indirectly. Every
// VAL of every light view sends the cache its perpendicular irradiance Φ/π · max(0, n·(-ω)) /
// (r² + A) from direction ω, projected as a delta lobe onto 2 or 3 SH bands, and times the
// visibility of its block: VALs are visited in Morton order within each light view, so every
// run of B² = 4^shadow_level VALs is one block, whose mean VAL (level `shadow_level` of the
// chain) one cone is traced to through the occupancy mips. Each thread reads every VAL as texels
// of the VAL chain's texel view: neighbouring threads read the same VAL, which a GPU's cache
// serves once and lavapipe fetches for all its lanes at once (it reads storage buffers and
// shared memory lane by lane at a loop's index: this pass took 0.7x the time it did staging the
// VALs in shared memory, docs/radiance-volumes.md). With indirect specular on, each
// VAL's light also goes to the texel of its half vector in the cache's hemisphere map (as a
// density, times side²/2π): one thread owns each map, so the read-modify-writes need no atomics.
#include "common/math.glsl"
#include "common/lights.glsl"
#include "gi/shared/sh.glsl"
#include "gi/radiance_volumes/state.glsl"
#include "gi/radiance_volumes/val.glsl"
#include "gi/radiance_volumes/specular.glsl"

layout(local_size_x = RV_LIGHT_GROUP) in;

layout(binding = RV_CACHES, std430) buffer Caches { vec4 caches[]; };
layout(binding = RV_SPECULAR, std430) buffer Specular { vec4 specular[]; };
// The VAL chain, four texels a VAL (gi/radiance_volumes/val.glsl's Val).
layout(binding = RV_VALS) uniform samplerBuffer vals;
layout(binding = RV_STATE, std430) readonly buffer State { RvState state; };
layout(binding = RV_VOXELS, std430) readonly buffer Voxels { float voxels[]; };
layout(binding = RV_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView views[]; };
#include "gi/radiance_volumes/voxel.glsl"

layout(push_constant) uniform Push {
    vec4 voxel_lo_size;   // the voxel cube's minimum corner, a voxel's side
    vec4 eye;             // xyz: the cascades' eye, which every cache's map faces
    uint capacity;
    uint stride;
    uint coefficients;    // 4 (L1) or 9 (L2)
    uint side;            // VALs per layer side of the read level
    uint layers;
    uint voxel_resolution;
    uint voxel_levels;
    uint shadow_level;    // chain level of the blocks' mean VALs (B = 2^shadow_level)
    uint shadow_first;    // first VAL of that level
    uint shadows;         // 0: every VAL visible
    uint cone_steps;      // most samples of a cone
    uint specular_side;   // side of a cache's hemisphere map (0: no indirect specular)
    uint specular_texels; // texels of one cache's map
} pc;

// The other bits of a Morton code's even (x) or odd (y) positions.
uint compact_bits(uint m) {
    m &= 0x55555555u;
    m = (m | (m >> 1)) & 0x33333333u;
    m = (m | (m >> 2)) & 0x0F0F0F0Fu;
    m = (m | (m >> 4)) & 0x00FF00FFu;
    m = (m | (m >> 8)) & 0x0000FFFFu;
    return m;
}

// The read-level VAL at Morton position j (layer-major), and its texel coordinates.
uvec3 morton_val(uint j) {
    uint per_layer = pc.side * pc.side;
    uint m = j % per_layer;
    return uvec3(compact_bits(m), compact_bits(m >> 1), j / per_layer);
}

// Visibility from x to the mean VAL of the block holding read-level VAL (xy, layer).
float block_visibility(VoxelGrid grid, vec3 x, uvec3 val) {
    uint side = pc.side >> pc.shadow_level;
    uvec2 block = val.xy >> pc.shadow_level;
    int first = 4 * int(pc.shadow_first + (val.z * side + block.y) * side + block.x);
    Val mean = Val(texelFetch(vals, first), texelFetch(vals, first + 1),
                   texelFetch(vals, first + 2), texelFetch(vals, first + 3));
    if (mean.position_texels.w == 0.0) return 1.0;
    float d = mean.flux_depth.w;
    float sigma = sqrt(max(mean.depth_squared.x - d * d, 0.0));
    // The block's angular width from the light, or two standard deviations of its depth,
    // whichever is wider (spec 001 §4.6 step 2; the view's extent uses tan, not sin).
    float width = views[val.z].params.w / float(side);
    float s = clamp(max(width, 2.0 * sigma / max(d, 1e-30)), 0.01, 0.95);
    float len = length(mean.normal_area.xyz);
    vec3 normal = len > 0.0 ? mean.normal_area.xyz / len : vec3(0.0, 0.0, 1.0);
    return cone_visibility(grid, x, mean.position_texels.xyz, normal, s,
                           sqrt(mean.normal_area.w), pc.cone_steps);
}

void main() {
    uint held = min(state.requested, pc.capacity);
    uint index = gl_GlobalInvocationID.x;
    if (index >= held) return;   // no cache to light (and no barrier to keep company)
    vec3 x = caches[index * pc.stride].xyz;
    VoxelGrid grid = VoxelGrid(pc.voxel_lo_size.xyz, pc.voxel_lo_size.w, pc.voxel_resolution,
                               pc.voxel_levels);
    uint block_mask = (1u << (2u * pc.shadow_level)) - 1u;
    uint val_count = pc.side * pc.side * pc.layers;
    float visibility = 1.0;
    vec3 c[SH_L2_COEFFICIENTS];
    for (uint i = 0u; i < SH_L2_COEFFICIENTS; ++i) c[i] = vec3(0.0);
    // The cache's map frame: z toward the eye.
    bool maps = pc.specular_side > 0u;
    uint map_first = index * pc.specular_texels;
    vec3 map_t = vec3(1.0, 0.0, 0.0);
    vec3 map_b = vec3(0.0, 1.0, 0.0);
    vec3 map_z = vec3(0.0, 0.0, 1.0);
    float density = float(pc.specular_side * pc.specular_side) / (2.0 * PI);
    if (maps) {
        vec3 to_eye = pc.eye.xyz - x;
        if (dot(to_eye, to_eye) > 0.0) map_z = normalize(to_eye);
        orthonormal_basis(map_z, map_t, map_b);
        for (uint i = 0u; i < pc.specular_side * pc.specular_side; ++i) specular[map_first + i] = vec4(0.0);
    }
    for (uint j = 0u; j < val_count; ++j) {
        uvec3 at = morton_val(j);
        if (pc.shadows != 0u && ((j % (pc.side * pc.side)) & block_mask) == 0u) {
            visibility = block_visibility(grid, x, at);
        }
        int v = 4 * int((at.z * pc.side + at.y) * pc.side + at.x);
        vec4 position_texels = texelFetch(vals, v);
        vec4 normal_area = texelFetch(vals, v + 1);
        float len = length(normal_area.xyz);
        bool lit = position_texels.w > 0.0 && len > 0.0;
        if (!lit || visibility == 0.0) continue;
        vec3 to = position_texels.xyz - x;
        float r2 = dot(to, to);
        if (r2 == 0.0) continue;
        vec3 w = to * inversesqrt(r2);
        float cos_val = dot(normal_area.xyz / len, -w);
        if (cos_val <= 0.0) continue;
        vec3 flux_over_pi = texelFetch(vals, v + 2).rgb * INV_PI;
        vec3 e = flux_over_pi * (visibility * cos_val / (r2 + normal_area.w));
        float y[SH_L2_COEFFICIENTS];
        sh_l2_basis(w, y);
        for (uint i = 0u; i < pc.coefficients; ++i) c[i] += e * y[i];
        if (maps) {
            uint texel = rv_specular_texel(vec3(dot(w, map_t), dot(w, map_b), dot(w, map_z)),
                                           pc.specular_side);
            if (texel != 0xFFFFFFFFu) specular[map_first + texel] += vec4(e * density, 0.0);
        }
    }
    for (uint i = 0u; i < pc.coefficients; ++i) caches[index * pc.stride + 1u + i] = vec4(c[i], 0.0);
}
