#version 460
// Indirect light from the lattice: at each surface point pushed --lookup-offset cells along its
// normal (default 1; the thesis: half a cell), the trilinearly interpolated SH intensity of the
// R, G and B lattices is projected on the cosine lobe toward the surface, SH_cos(-n), turned
// into radiance by the cell area and added, times albedo / pi, to the HDR image.
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/lpv/lattice.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = LOOKUP_LATTICE_R, std430) readonly buffer LatticeR { vec4 lattice_r[]; };
layout(binding = LOOKUP_LATTICE_G, std430) readonly buffer LatticeG { vec4 lattice_g[]; };
layout(binding = LOOKUP_LATTICE_B, std430) readonly buffer LatticeB { vec4 lattice_b[]; };
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
    vec3 u = (p - pc.origin_cell.xyz) / pc.origin_cell.w - 0.5;
    ivec3 base = ivec3(floor(u));
    vec3 f = u - vec3(base);
    vec4 lobe = sh_cosine_lobe(-n);
    vec3 incident = vec3(0.0);
    for (int k = 0; k < 8; ++k) {
        ivec3 corner = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        ivec3 c = base + corner;
        if (!lattice_inside(c, pc.dims.xyz)) continue;
        vec3 w3 = mix(1.0 - f, f, vec3(corner));
        float w = w3.x * w3.y * w3.z;
        uint i = lattice_index(c, pc.dims.xyz);
        incident += w * vec3(dot(lattice_r[i], lobe), dot(lattice_g[i], lobe), dot(lattice_b[i], lobe));
    }
    vec3 radiance = albedo * max(incident, vec3(0.0)) * pc.scale;
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(radiance, 0.0));
}
