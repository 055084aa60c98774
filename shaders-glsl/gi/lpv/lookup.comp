#version 460
// Indirect light from the lattice: at each surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices is projected on the cosine lobe toward the surface, SH_cos(-n), turned
// into radiance by the cell area and added, times albedo / pi, to the HDR image.
#include "common/math.glsl"
#include "gi/shared/sh.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
// The R, G and B lattices as 3-D images: the sampler's trilinear filter interpolates the eight
// cells around a point, with transparent black (no light) outside the lattice.
layout(binding = LOOKUP_LATTICE_R) uniform sampler3D lattice_r;
layout(binding = LOOKUP_LATTICE_G) uniform sampler3D lattice_g;
layout(binding = LOOKUP_LATTICE_B) uniform sampler3D lattice_b;
layout(binding = LOOKUP_HDR, rgba32f) uniform image2D hdr;

layout(push_constant) uniform Push {
    vec4 origin_cell;   // xyz lattice origin, w cell size
    ivec4 dims;
    uvec2 size;
    float scale;        // 1 / (pi cell²): intensity per cell -> radiance, times albedo / pi
    float offset;       // along the normal, in cells (the thesis: 0.5)
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0) return;
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 p = position.xyz + n * (pc.offset * pc.origin_cell.w);
    // Cell c's centre lies at texture coordinate (c + 0.5) / dims.
    vec3 t = (p - pc.origin_cell.xyz) / (pc.origin_cell.w * vec3(pc.dims.xyz));
    vec4 lobe = sh_cosine_lobe(-n);
    vec3 incident = vec3(dot(textureLod(lattice_r, t, 0.0), lobe),
                         dot(textureLod(lattice_g, t, 0.0), lobe),
                         dot(textureLod(lattice_b, t, 0.0), lobe));
    vec3 radiance = albedo * max(incident, vec3(0.0)) * pc.scale;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
