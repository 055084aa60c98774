#version 460
// Per surface: the area-weighted mean unshot (reflected) radiosity and the unshot power,
// (mean reflected + unshot emission) x area; and of importance (id, pd): the mean unshot
// importance, the largest total importance of any element (the thesis's max-reduction, so a
// small, important, partly hidden region is not averaged away, spec 004 pass B3) and the unshot
// importance's |ΔI| x area. One workgroup per surface.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { Surface surfaces[]; };
layout(binding = RAD_ELEMENTS, std430) readonly buffer Elements { Element elements[]; };
layout(binding = RAD_UNSHOT, std430) readonly buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) readonly buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_IMPORTANCE, std430) readonly buffer Importance { float importance[]; };
layout(binding = RAD_IMPORTANCE_UNSHOT, std430) readonly buffer ImportanceUnshot { float importance_unshot[]; };
layout(binding = RAD_STATS, std430) writeonly buffer Stats { vec4 stats[]; };
layout(binding = RAD_IMPORTANCE_STATS, std430) writeonly buffer ImportanceStats { vec4 importance_stats[]; };

layout(push_constant) uniform Push {
    uint surface_count;
} pc;

shared vec4 partial[LINEAR_WORKGROUP];
shared vec4 partial_importance[LINEAR_WORKGROUP];

void main() {
    uint s = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (s >= pc.surface_count) return;
    Surface surface = surfaces[s];
    uint count = surface.grid.y * surface.grid.z;
    vec4 sum = vec4(0.0);
    vec4 imp = vec4(0.0);
    for (uint i = gl_LocalInvocationID.x; i < count; i += LINEAR_WORKGROUP) {
        uint e = surface.grid.x + i;
        float area = elements[e].position_area.w;
        if (area <= 0.0) continue;
        sum += vec4(unshot[e].rgb * area, area);
        float d = importance_unshot[e];
        imp += vec4(d * area, abs(d) * area, 0.0, 0.0);
        imp.z = max(imp.z, importance[e]);
    }
    partial[gl_LocalInvocationID.x] = sum;
    partial_importance[gl_LocalInvocationID.x] = imp;
    barrier();
    for (uint stride = LINEAR_WORKGROUP / 2u; stride > 0u; stride /= 2u) {
        uint lane = gl_LocalInvocationID.x;
        if (lane < stride) {
            partial[lane] += partial[lane + stride];
            vec4 other = partial_importance[lane + stride];
            vec4 mine = partial_importance[lane];
            partial_importance[lane] = vec4(mine.xy + other.xy, max(mine.z, other.z), 0.0);
        }
        barrier();
    }
    if (gl_LocalInvocationID.x == 0u) {
        vec4 total = partial[0];
        vec4 imp_total = partial_importance[0];
        vec3 mean = total.w > 0.0 ? total.rgb / total.w : vec3(0.0);
        vec3 emitted = emission_unshot[s] != 0u ? surface.emission.rgb : vec3(0.0);
        stats[s] = vec4(mean, (mean3(mean) + mean3(emitted)) * surface.axis_t_area.w);
        float mean_importance = total.w > 0.0 ? imp_total.x / total.w : 0.0;
        importance_stats[s] = vec4(mean_importance, imp_total.z, imp_total.y, 0.0);
    }
}
