#version 460
// One level of the VAL mip chain (spec 001 §4.3): each VAL the merge of a 2x2 block of the level
// below, flux, normals and area summed, position and distance moments averaged over covered
// texels (cpu.rs `Val::merge`).
#include "gi/radiance_volumes/val.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = RV_VALS, std430) buffer Vals { Val vals[]; };

layout(push_constant) uniform Push {
    uint source;      // first VAL of the level below
    uint target;      // first VAL of this level
    uint side;        // VALs per layer side of this level
    uint layers;
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.side || id.y >= pc.side || id.z >= pc.layers) return;
    uint below = 2u * pc.side;
    vec3 position = vec3(0.0);
    vec4 normal_area = vec4(0.0);
    vec3 flux = vec3(0.0);
    float texels = 0.0;
    float depth = 0.0;
    float depth_squared = 0.0;
    for (uint k = 0u; k < 4u; ++k) {
        uvec2 c = 2u * id.xy + uvec2(k & 1u, k >> 1);
        Val child = vals[pc.source + (id.z * below + c.y) * below + c.x];
        float n = child.position_texels.w;
        position += child.position_texels.xyz * n;
        normal_area += child.normal_area;
        flux += child.flux_depth.rgb;
        texels += n;
        depth += child.flux_depth.w * n;
        depth_squared += child.depth_squared.x * n;
    }
    float inv = texels > 0.0 ? 1.0 / texels : 0.0;
    vals[pc.target + (id.z * pc.side + id.y) * pc.side + id.x] = Val(
        vec4(position * inv, texels),
        normal_area,
        vec4(flux, depth * inv),
        vec4(depth_squared * inv, 0.0, 0.0, 0.0));
}
