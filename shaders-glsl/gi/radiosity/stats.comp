#version 460
// Per surface: the area-weighted mean unshot (reflected) radiosity and the unshot power,
// (mean reflected + unshot emission) x area. One workgroup per surface.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { Surface surfaces[]; };
layout(binding = RAD_ELEMENTS, std430) readonly buffer Elements { Element elements[]; };
layout(binding = RAD_UNSHOT, std430) readonly buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) readonly buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_STATS, std430) writeonly buffer Stats { vec4 stats[]; };

layout(push_constant) uniform Push {
    uint surface_count;
} pc;

shared vec4 partial[LINEAR_WORKGROUP];

void main() {
    uint s = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (s >= pc.surface_count) return;
    Surface surface = surfaces[s];
    uint count = surface.grid.y * surface.grid.z;
    vec4 sum = vec4(0.0);
    for (uint i = gl_LocalInvocationID.x; i < count; i += LINEAR_WORKGROUP) {
        uint e = surface.grid.x + i;
        float area = elements[e].position_area.w;
        sum += vec4(unshot[e].rgb * area, area);
    }
    partial[gl_LocalInvocationID.x] = sum;
    barrier();
    for (uint stride = LINEAR_WORKGROUP / 2u; stride > 0u; stride /= 2u) {
        if (gl_LocalInvocationID.x < stride) {
            partial[gl_LocalInvocationID.x] += partial[gl_LocalInvocationID.x + stride];
        }
        barrier();
    }
    if (gl_LocalInvocationID.x == 0u) {
        vec4 total = partial[0];
        vec3 mean = total.w > 0.0 ? total.rgb / total.w : vec3(0.0);
        vec3 emitted = emission_unshot[s] != 0u ? surface.emission.rgb : vec3(0.0);
        stats[s] = vec4(mean, (mean3(mean) + mean3(emitted)) * surface.axis_t_area.w);
    }
}
