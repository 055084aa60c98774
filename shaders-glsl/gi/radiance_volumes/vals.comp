#version 460
// The VALs the caches are lit by (spec 001 §4.3): each is a block of 2^lod x 2^lod texels of one
// RSM layer, summing their reflected flux and their area across the light's rays (d^2 times the
// texel's solid angle, (extent / size)^2 cos^3 of its angle to the view axis, as rsm.frag has
// it), and averaging position and distance over the texels that saw a surface.
#include "common/lights.glsl"
#include "gi/radiance_volumes/val.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = RV_RSM_POSITION, rgba32f) readonly uniform image2DArray rsm_position;
layout(binding = RV_RSM_NORMAL, rgba16f) readonly uniform image2DArray rsm_normal;
layout(binding = RV_RSM_FLUX, rgba32f) readonly uniform image2DArray rsm_flux;
layout(binding = RV_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView views[]; };
layout(binding = RV_VALS, std430) writeonly buffer Vals { Val vals[]; };

layout(push_constant) uniform Push {
    uint rsm_size;
    uint side;        // VALs per layer side
    uint block;       // texels per VAL side
    uint layers;
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.side || id.y >= pc.side || id.z >= pc.layers) return;
    ShadowView view = views[id.z];
    float texel = view.params.w / float(pc.rsm_size);
    vec3 position = vec3(0.0);
    vec3 normal = vec3(0.0);
    vec3 flux = vec3(0.0);
    float area = 0.0;
    float texels = 0.0;
    float depth = 0.0;
    float depth_squared = 0.0;
    for (uint v = 0u; v < pc.block; ++v) {
        for (uint u = 0u; u < pc.block; ++u) {
            ivec3 t = ivec3(id.xy * pc.block + uvec2(u, v), id.z);
            vec4 p = imageLoad(rsm_position, t);
            if (p.w == 0.0) continue;
            vec3 to = p.xyz - view.origin.xyz;
            float d = length(to);
            float cos_axis = d > 0.0 ? max(dot(view.axis_light.xyz, to / d), 0.0) : 0.0;
            position += p.xyz;
            normal += imageLoad(rsm_normal, t).xyz;
            flux += imageLoad(rsm_flux, t).rgb;
            area += d * d * texel * texel * cos_axis * cos_axis * cos_axis;
            texels += 1.0;
            depth += d;
            depth_squared += d * d;
        }
    }
    float inv = texels > 0.0 ? 1.0 / texels : 0.0;
    vals[(id.z * pc.side + id.y) * pc.side + id.x] = Val(
        vec4(position * inv, texels),
        vec4(normal, area),
        vec4(flux, depth * inv),
        vec4(depth_squared * inv, 0.0, 0.0, 0.0));
}
