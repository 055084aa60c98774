#ifndef VKGI_LPV_LOOKUP_LIGHT_GLSL
#define VKGI_LPV_LOOKUP_LIGHT_GLSL
// The fragment side of the lookup: at a surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices projected on the cosine lobe toward the surface, SH_cos(-n), turned into
// radiance by the cell area, times albedo / pi. ILPV's two scales look up both lattices, each
// field clamped at zero on its own. The fields' constants arrive as flat varyings from location
// LOOKUP_FIELDS_LOCATION on (lpv/lookup_fields.glsl), or in the compute form (LOOKUP_COMPUTE 1)
// from the fields' buffer.
//
// How the lattices are read (--lookup-filter, src/gi/lpv/lookup.rs LookupFilter), by the
// including shader's LOOKUP_TEXELS: 0, 3-D copies of the lattices inside a border of zero cells,
// which the sampler filters trilinearly (one fetch per channel: a GPU's texture unit); 1, the
// lattice buffers themselves as texels, the eight cells around the point fetched and weighted
// here (lavapipe filters a 3-D image in software, at about twice the cost of these fetches),
// each pixel fetching its own eight, or with LOOKUP_SHARED_CORNERS 1 the subgroup's lanes
// fetching them together.
#extension GL_EXT_control_flow_attributes : require
#include "common/math.glsl"
#include "gi/shared/sh.glsl"

#ifndef LOOKUP_FIELDS_LOCATION
#define LOOKUP_FIELDS_LOCATION 0
#endif
#ifndef LOOKUP_TEXELS
#define LOOKUP_TEXELS 0
#endif
#ifndef LOOKUP_COMPUTE
#define LOOKUP_COMPUTE 0
#endif
// With LOOKUP_TEXELS, 1: the subgroup's lanes share the fetches of the cells around their points.
#ifndef LOOKUP_SHARED_CORNERS
#define LOOKUP_SHARED_CORNERS 0
#endif

// 1: one lattice; 2: the near and the far field of two scales.
layout(constant_id = LOOKUP_FIELDS_CONSTANT) const uint FIELDS = 1u;

#if LOOKUP_TEXELS
#include "gi/lpv/lattice.glsl"
// Each field's R, G and B lattices as texels, in rows or in columns as the field's constants
// say (lpv/lattice.glsl's cell_strides).
#define LATTICE_READS samplerBuffer
#else
// Each field's R, G and B lattices as 3-D images: the sampler's trilinear filter interpolates
// the eight cells around a point. The images hold a border of zero cells around the lattice and
// the sampler clamps to their edge: transparent black (no light) outside the lattice.
#define LATTICE_READS sampler3D
#endif
layout(binding = LOOKUP_LATTICE_R) uniform LATTICE_READS lattice_r;
layout(binding = LOOKUP_LATTICE_G) uniform LATTICE_READS lattice_g;
layout(binding = LOOKUP_LATTICE_B) uniform LATTICE_READS lattice_b;
layout(binding = LOOKUP_FAR_LATTICE_R) uniform LATTICE_READS far_lattice_r;
layout(binding = LOOKUP_FAR_LATTICE_G) uniform LATTICE_READS far_lattice_g;
layout(binding = LOOKUP_FAR_LATTICE_B) uniform LATTICE_READS far_lattice_b;

// The fields' constants (lpv/lookup_fields.glsl), the same for every fragment: per field the
// corner of what it reads (the images' border included) and the cell size, its cells and
// whether its texels hold them in columns, and (scale, offset).
#if LOOKUP_COMPUTE
// The compute form has no varyings: its main fills these from the fields' buffer
// (lpv/lookup_fields.glsl's field_words) before it looks anything up.
vec4 fields[LOOKUP_FIELD_WORDS];
#else
layout(location = LOOKUP_FIELDS_LOCATION) flat in vec4 fields[LOOKUP_FIELD_WORDS];
#endif

#if LOOKUP_TEXELS
// The eight cells around a point: the cell below it on every axis (which may lie outside the
// lattice) and each axis's weights of that cell and the next (zero for a cell outside).
struct Corners {
    ivec3 base;
    vec2 wx;
    vec2 wy;
    vec2 wz;
};

// The cells around the point at `d` from the corner of a lattice of `dims` cells of size
// `cell`.
Corners corners_around(vec3 d, float cell, vec3 dims) {
    // Cell c's centre lies at u = c.
    vec3 u = d / cell - 0.5;
    vec3 base = floor(u);
    vec3 f = u - base;
    vec3 low = (1.0 - f) * step(0.0, base) * step(base, dims - 1.0);
    vec3 high = f * step(-1.0, base) * step(base, dims - 2.0);
    return Corners(ivec3(base), vec2(low.x, high.x), vec2(low.y, high.y), vec2(low.z, high.z));
}

// Corner k (0-7: x fastest, then y, then z) of the cells above `base`, as an offset.
ivec3 corner_offset(uint k) {
    return ivec3(k & 1u, (k >> 1u) & 1u, k >> 2u);
}

// Corner k's weight in `c`.
float corner_weight(Corners c, uint k) {
    return c.wz[k >> 2u] * c.wy[(k >> 1u) & 1u] * c.wx[k & 1u];
}

// The texel of cell `base + offset`, clamped inside a lattice of `n` cells whose neighbours lie
// `strides` apart (a clamped cell's weight is zero).
int corner_texel(ivec3 base, ivec3 offset, ivec3 n, ivec3 strides) {
    ivec3 c = clamp(base + offset, ivec3(0), n - 1);
    return c.x * strides.x + c.y * strides.y + c.z * strides.z;
}

#if LOOKUP_SHARED_CORNERS
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_KHR_shader_subgroup_vote : require
// The trilinear interpolation of the lattices `r`, `g` and `b` of `dims` cells of size `cell` at
// `d` from their corner, their cells in columns or rows, as the per-pixel form below computes it
// (the same corners, weights and order of sums), the fetches shared across the subgroup
// (--lookup-filter shared-texels): neighbouring pixels mostly lie among the same eight cells, so
// lane k (0-7) fetches corner k of the first waiting lane's cells, every lane whose point lies
// among them takes all eight by shuffles, and the next waiting lane leads the next round: a
// round per set of cells the subgroup's points fall in (1.6 on average for a batch of 8 pixels
// of the Cornell box in a 32³ lattice at 800x600, 2.4 at 64³), 3 fetches a lane each, where
// the per-pixel form makes 24. A
// subgroup with inactive lanes cannot lend their fetches, so there each lane fetches its own
// eight corners, one a round.
mat3x4 interpolate(samplerBuffer r, samplerBuffer g, samplerBuffer b, vec3 d, float cell, vec3 dims,
                   bool columns) {
    Corners c = corners_around(d, cell, dims);
    ivec3 n = ivec3(dims);
    ivec3 strides = cell_strides(n, columns);
    bool whole = subgroupBallotBitCount(subgroupBallot(true)) == gl_SubgroupSize;
    ivec3 lent = corner_offset(gl_SubgroupInvocationID & 7u);
    mat3x4 sum = mat3x4(0.0);
    bool served = false;
    // In a subgroup short of lanes, the corner a lane fetches next.
    uint own = 0u;
    do {
        ivec3 lead = subgroupShuffle(c.base, subgroupBallotFindLSB(subgroupBallot(!served)));
        int texel = whole ? corner_texel(lead, lent, n, strides)
                          : corner_texel(c.base, corner_offset(own), n, strides);
        vec4 tr = texelFetch(r, texel);
        vec4 tg = texelFetch(g, texel);
        vec4 tb = texelFetch(b, texel);
        if (whole) {
            mat3x4 lead_sum = mat3x4(0.0);
            [[unroll]] for (uint k = 0u; k < 8u; ++k) {
                float w = corner_weight(c, k);
                lead_sum[0] += w * subgroupShuffle(tr, k);
                lead_sum[1] += w * subgroupShuffle(tg, k);
                lead_sum[2] += w * subgroupShuffle(tb, k);
            }
            if (!served && all(equal(c.base, lead))) {
                sum = lead_sum;
                served = true;
            }
        } else {
            float w = corner_weight(c, own);
            sum[0] += w * tr;
            sum[1] += w * tg;
            sum[2] += w * tb;
            own += 1u;
            served = own == 8u;
        }
    } while (subgroupAny(!served));
    return sum;
}
#else
// The trilinear interpolation of the lattices `r`, `g` and `b` of `dims` cells of size `cell` at
// `d` from their corner, their cells in columns (z fastest) or rows; cells outside the lattice
// count as empty (their weight zero, their index clamped inside).
mat3x4 interpolate(samplerBuffer r, samplerBuffer g, samplerBuffer b, vec3 d, float cell, vec3 dims,
                   bool columns) {
    Corners c = corners_around(d, cell, dims);
    ivec3 n = ivec3(dims);
    ivec3 strides = cell_strides(n, columns);
    mat3x4 sum = mat3x4(0.0);
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
        int texel = corner_texel(c.base, corner_offset(k), n, strides);
        float w = corner_weight(c, k);
        sum[0] += w * texelFetch(r, texel);
        sum[1] += w * texelFetch(g, texel);
        sum[2] += w * texelFetch(b, texel);
    }
    return sum;
}
#endif
#else
// The sampler's trilinear filter of the images `r`, `g` and `b` of `dims` texels of size `cell`
// at `d` from their corner (images hold rows: `columns` is false).
mat3x4 interpolate(sampler3D r, sampler3D g, sampler3D b, vec3 d, float cell, vec3 dims,
                   bool columns) {
    // Texel c's centre lies at texture coordinate (c + 0.5) / dims.
    vec3 t = d / (cell * dims);
    return mat3x4(textureLod(r, t, 0.0), textureLod(g, t, 0.0), textureLod(b, t, 0.0));
}
#endif

// Field `f`'s intensity toward the surface at `position` (normal `n`), clamped at zero.
vec3 field_light(int f, LATTICE_READS r, LATTICE_READS g, LATTICE_READS b, vec3 position, vec3 n,
                 vec4 lobe) {
    vec4 origin_cell = fields[3 * f];
    vec3 dims = fields[3 * f + 1].xyz;
    bool columns = fields[3 * f + 1].w != 0.0;
    vec4 scale_offset = fields[3 * f + 2];
    vec3 p = position + n * (scale_offset.y * origin_cell.w);
    mat3x4 sh = interpolate(r, g, b, p - origin_cell.xyz, origin_cell.w, dims, columns);
    vec3 incident = vec3(dot(sh[0], lobe), dot(sh[1], lobe), dot(sh[2], lobe));
    return max(incident, vec3(0.0));
}

// The indirect radiance a surface at `position` (unit normal `n`, albedo `albedo`) reflects.
vec3 lattice_radiance(vec3 position, vec3 n, vec3 albedo) {
    vec4 lobe = sh_cosine_lobe(-n);
    vec3 value = albedo * field_light(0, lattice_r, lattice_g, lattice_b, position, n, lobe)
                 * fields[2].x;
    if (FIELDS > 1u) {
        value += albedo * field_light(1, far_lattice_r, far_lattice_g, far_lattice_b, position, n,
                                      lobe) * fields[5].x;
    }
    return value;
}

#endif
