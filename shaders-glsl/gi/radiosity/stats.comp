#version 460
// Per surface: the area-weighted mean unshot (reflected) radiosity and the unshot power,
// (mean reflected + unshot emission) x area; and of importance (id, pd): the mean unshot
// importance, the largest total importance of any element (the thesis's max-reduction, so a
// small, important, partly hidden region is not averaged away, spec 004 pass B3) and the unshot
// importance's |ΔI| x area. One subgroup per surface, its lanes taking the surface's elements in
// turn and summing them with subgroup arithmetic: no barriers, and a scene of many small
// surfaces (the atrium's 12 815, about one element each) does not pay a workgroup's reduction
// for each. The subgroups stride over the surfaces, so any number of workgroups covers them.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { SurfaceRecord surfaces[]; };
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

void main() {
    uint subgroups = gl_NumWorkGroups.x * gl_NumSubgroups;
    for (uint s = gl_WorkGroupID.x * gl_NumSubgroups + gl_SubgroupID; s < pc.surface_count;
         s += subgroups) {
        uvec4 grid = surfaces[s].grid;
        uint count = grid.y * grid.z;
        vec4 sum = vec4(0.0);
        vec3 imp = vec3(0.0);
        for (uint i = gl_SubgroupInvocationID; i < count; i += gl_SubgroupSize) {
            uint e = grid.x + i;
            float area = elements[e].position_area.w;
            if (area <= 0.0) continue;
            sum += vec4(unshot[e].rgb * area, area);
            float d = importance_unshot[e];
            imp += vec3(d * area, abs(d) * area, 0.0);
            imp.z = max(imp.z, importance[e]);
        }
        vec4 total = subgroupAdd(sum);
        vec2 imp_total = subgroupAdd(imp.xy);
        float imp_max = subgroupMax(imp.z);
        if (subgroupElect()) {
            vec3 mean = total.w > 0.0 ? total.rgb / total.w : vec3(0.0);
            vec3 emitted = emission_unshot[s] != 0u ? surfaces[s].emission.rgb : vec3(0.0);
            stats[s] = vec4(mean, (mean3(mean) + mean3(emitted)) * surfaces[s].axis_t_area.w);
            float mean_importance = total.w > 0.0 ? imp_total.x / total.w : 0.0;
            importance_stats[s] = vec4(mean_importance, imp_max, imp_total.y, 0.0);
        }
    }
}
