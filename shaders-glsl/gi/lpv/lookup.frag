#version 460
// Indirect light from the lattice: at each surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices is projected on the cosine lobe toward the surface, SH_cos(-n), turned
// into radiance by the cell area and added, times albedo / pi, to the HDR image. ILPV's two
// scales look up both lattices in one pass, each field clamped at zero on its own.
// A fragment pass over a full-screen triangle (common/fullscreen.vert) whose output the blend
// adds to the HDR image: on lavapipe the render target's blend costs a fraction of a compute
// pass's imageLoad and imageStore of the same pixel (docs/performance.md).
#include "common/math.glsl"
#include "gi/shared/sh.glsl"

// 1: one lattice; 2: the near and the far field of two scales.
layout(constant_id = 0) const uint FIELDS = 1u;

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
// Each field's R, G and B lattices as 3-D images: the sampler's trilinear filter interpolates
// the eight cells around a point, with transparent black (no light) outside the lattice.
layout(binding = LOOKUP_LATTICE_R) uniform sampler3D lattice_r;
layout(binding = LOOKUP_LATTICE_G) uniform sampler3D lattice_g;
layout(binding = LOOKUP_LATTICE_B) uniform sampler3D lattice_b;
layout(binding = LOOKUP_FAR_LATTICE_R) uniform sampler3D far_lattice_r;
layout(binding = LOOKUP_FAR_LATTICE_G) uniform sampler3D far_lattice_g;
layout(binding = LOOKUP_FAR_LATTICE_B) uniform sampler3D far_lattice_b;
// Added to the HDR image by the blend (one plus one).
layout(location = 0) out vec4 out_indirect;

layout(push_constant) uniform Push {
    vec4 origin_cell[2];   // per field: xyz lattice origin, w cell size
    ivec4 dims[2];
    vec4 scale_offset[2];  // x: 1 / (pi cell²) times the method's scale; y: the offset in cells
} pc;

// Field `f`'s intensity toward the surface at `position` (normal `n`), clamped at zero.
vec3 field_light(uint f, sampler3D r, sampler3D g, sampler3D b, vec3 position, vec3 n, vec4 lobe) {
    vec4 origin_cell = pc.origin_cell[f];
    vec3 p = position + n * (pc.scale_offset[f].y * origin_cell.w);
    // Cell c's centre lies at texture coordinate (c + 0.5) / dims.
    vec3 t = (p - origin_cell.xyz) / (origin_cell.w * vec3(pc.dims[f].xyz));
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
    vec3 value = albedo * field_light(0u, lattice_r, lattice_g, lattice_b, position.xyz, n, lobe)
                 * pc.scale_offset[0].x;
    if (FIELDS > 1u) {
        value += albedo * field_light(1u, far_lattice_r, far_lattice_g, far_lattice_b,
                                      position.xyz, n, lobe) * pc.scale_offset[1].x;
    }
    // Background pixels (w = 0) get nothing.
    out_indirect = vec4(position.w != 0.0 ? value : vec3(0.0), 0.0);
}
