#version 460
// Indirect light from the lattice: at each surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices is projected on the cosine lobe toward the surface, SH_cos(-n), turned
// into radiance by the cell area and added, times albedo / pi, to the HDR image. ILPV's two
// scales look up both lattices in one pass, each field clamped at zero on its own.
// A fragment pass over a full-screen triangle (gi/lpv/lookup.vert, which hands it the fields'
// constants as flat varyings) whose output the blend adds to the HDR image: on lavapipe the render target's blend costs a fraction of a compute
// pass's imageLoad and imageStore of the same pixel (docs/performance.md).
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/lpv/lookup_fields.glsl"

// 1: one lattice; 2: the near and the far field of two scales.
layout(constant_id = 0) const uint FIELDS = 1u;

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
// Each field's R, G and B lattices as 3-D images: the sampler's trilinear filter interpolates
// the eight cells around a point. The images hold a border of zero cells around the lattice and
// the sampler clamps to their edge: transparent black (no light) outside the lattice.
layout(binding = LOOKUP_LATTICE_R) uniform sampler3D lattice_r;
layout(binding = LOOKUP_LATTICE_G) uniform sampler3D lattice_g;
layout(binding = LOOKUP_LATTICE_B) uniform sampler3D lattice_b;
layout(binding = LOOKUP_FAR_LATTICE_R) uniform sampler3D far_lattice_r;
layout(binding = LOOKUP_FAR_LATTICE_G) uniform sampler3D far_lattice_g;
layout(binding = LOOKUP_FAR_LATTICE_B) uniform sampler3D far_lattice_b;
// Added to the HDR image by the blend (one plus one).
layout(location = 0) out vec4 out_indirect;

// The fields' constants (lpv/lookup_fields.glsl), the same for every fragment.
layout(location = 0) flat in vec4 fields[FIELD_WORDS];

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

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec4 lobe = sh_cosine_lobe(-n);
    vec3 value = albedo * field_light(0, lattice_r, lattice_g, lattice_b, position.xyz, n, lobe)
                 * fields[2].x;
    if (FIELDS > 1u) {
        value += albedo * field_light(1, far_lattice_r, far_lattice_g, far_lattice_b,
                                      position.xyz, n, lobe) * fields[5].x;
    }
    // Background pixels (w = 0) get nothing.
    out_indirect = vec4(position.w != 0.0 ? value : vec3(0.0), 0.0);
}
