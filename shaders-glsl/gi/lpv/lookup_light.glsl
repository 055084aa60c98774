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
// here (lavapipe filters a 3-D image in software, at about twice the cost of these fetches).
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
// The trilinear interpolation of the lattices `r`, `g` and `b` of `dims` cells of size `cell` at
// `d` from their corner, their cells in columns (z fastest) or rows; cells outside the lattice
// count as empty (their weight zero, their index clamped inside).
mat3x4 interpolate(samplerBuffer r, samplerBuffer g, samplerBuffer b, vec3 d, float cell, vec3 dims,
                   bool columns) {
    // Cell c's centre lies at u = c.
    vec3 u = d / cell - 0.5;
    vec3 base = floor(u);
    vec3 f = u - base;
    vec3 low = (1.0 - f) * step(0.0, base) * step(base, dims - 1.0);
    vec3 high = f * step(-1.0, base) * step(base, dims - 2.0);
    ivec3 n = ivec3(dims);
    ivec3 first = clamp(ivec3(base), ivec3(0), n - 1);
    ivec3 second = clamp(ivec3(base) + 1, ivec3(0), n - 1);
    ivec3 s = cell_strides(n, columns);
    int x[2] = int[2](first.x * s.x, second.x * s.x);
    int y[2] = int[2](first.y * s.y, second.y * s.y);
    int z[2] = int[2](first.z * s.z, second.z * s.z);
    vec2 wx = vec2(low.x, high.x);
    vec2 wy = vec2(low.y, high.y);
    vec2 wz = vec2(low.z, high.z);
    mat3x4 sum = mat3x4(0.0);
    [[unroll]] for (int k = 0; k < 2; ++k) {
        [[unroll]] for (int j = 0; j < 2; ++j) {
            [[unroll]] for (int i = 0; i < 2; ++i) {
                int index = z[k] + y[j] + x[i];
                float w = wz[k] * wy[j] * wx[i];
                sum[0] += w * texelFetch(r, index);
                sum[1] += w * texelFetch(g, index);
                sum[2] += w * texelFetch(b, index);
            }
        }
    }
    return sum;
}
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
