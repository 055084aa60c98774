#ifndef VKGI_LPV_LOOKUP_LIGHT_GLSL
#define VKGI_LPV_LOOKUP_LIGHT_GLSL
// The fragment side of the lookup: at a surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices projected on the cosine lobe toward the surface, SH_cos(-n), turned into
// radiance by the cell area, times albedo / pi. ILPV's two scales look up both lattices, each
// field clamped at zero on its own. The fields' constants arrive as flat varyings from location
// LOOKUP_FIELDS_LOCATION on (lpv/lookup_fields.glsl).
#include "common/math.glsl"
#include "gi/shared/sh.glsl"

#ifndef LOOKUP_FIELDS_LOCATION
#define LOOKUP_FIELDS_LOCATION 0
#endif

// 1: one lattice; 2: the near and the far field of two scales.
layout(constant_id = LOOKUP_FIELDS_CONSTANT) const uint FIELDS = 1u;

// Each field's R, G and B lattices as 3-D images: the sampler's trilinear filter interpolates
// the eight cells around a point. The images hold a border of zero cells around the lattice and
// the sampler clamps to their edge: transparent black (no light) outside the lattice.
layout(binding = LOOKUP_LATTICE_R) uniform sampler3D lattice_r;
layout(binding = LOOKUP_LATTICE_G) uniform sampler3D lattice_g;
layout(binding = LOOKUP_LATTICE_B) uniform sampler3D lattice_b;
layout(binding = LOOKUP_FAR_LATTICE_R) uniform sampler3D far_lattice_r;
layout(binding = LOOKUP_FAR_LATTICE_G) uniform sampler3D far_lattice_g;
layout(binding = LOOKUP_FAR_LATTICE_B) uniform sampler3D far_lattice_b;

// The fields' constants (lpv/lookup_fields.glsl), the same for every fragment.
layout(location = LOOKUP_FIELDS_LOCATION) flat in vec4 fields[LOOKUP_FIELD_WORDS];

// Field `f`'s intensity toward the surface at `position` (normal `n`), clamped at zero.
vec3 field_light(int f, sampler3D r, sampler3D g, sampler3D b, vec3 position, vec3 n, vec4 lobe) {
    vec4 origin_cell = fields[3 * f];
    vec3 dims = fields[3 * f + 1].xyz;
    vec4 scale_offset = fields[3 * f + 2];
    vec3 p = position + n * (scale_offset.y * origin_cell.w);
    // Cell c's centre lies at texture coordinate (c + 0.5) / dims.
    vec3 t = (p - origin_cell.xyz) / (origin_cell.w * dims);
    vec3 incident = vec3(dot(textureLod(r, t, 0.0), lobe),
                         dot(textureLod(g, t, 0.0), lobe),
                         dot(textureLod(b, t, 0.0), lobe));
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
