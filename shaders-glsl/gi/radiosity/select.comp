#version 460
// The next shooter (spec 004 pass A1, a reduction instead of the thesis's 1-pixel depth test).
// pr: the surface of most unshot power. id/pd (pass B3): of most importance-weighted power,
// max I x unshot power, falling back to the most unshot power when the important surfaces are
// spent: when no surface's weighted power exceeds epsilon times the most power there was times
// the largest importance (also while nothing has importance yet). Without the fallback, id
// would shoot ever smaller amounts in view forever and never light (or converge) the rest. An importance shot (pass B2): the surface of most |ΔI| x area.
// A radiosity selection also writes the ambient term still to arrive (§4.1.6, split so the
// direct part the rasteriser already draws is not counted twice). Converged: no surface has
// more than epsilon times the most the shot quantity's total ever was.
#include "gi/radiosity/radiosity.glsl"

#define SELECT_POWER 0u
#define SELECT_IMPORTANCE_WEIGHTED 1u
#define SELECT_IMPORTANCE_SHOOTER 2u

layout(local_size_x = 256) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { SurfaceRecord surfaces[]; };
layout(binding = RAD_STATS, std430) readonly buffer Stats { vec4 stats[]; };
layout(binding = RAD_IMPORTANCE_STATS, std430) readonly buffer ImportanceStats { vec4 importance_stats[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) readonly buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_SHOT, std430) buffer ShotBuffer { Shot shot; };

layout(push_constant) uniform Push {
    vec4 reflectance_sum;  // rgb 1 / (1 - mean albedo): every bounce of the ambient term
    uint surface_count;
    float total_area;
    float epsilon;         // converged below this fraction of the most unshot power
    uint mode;             // SELECT_*
} pc;

shared float best_value[256];
shared uint best_index[256];
shared float fallback_value[256];
shared uint fallback_index[256];
shared float importance_max[256];
shared vec4 reflected_sum[256];
shared vec4 emitted_sum[256];

// Whether (value b, index ib) beats (a, ia): larger, or equal with the smaller index.
bool beats(float b, uint ib, float a, uint ia) {
    return b > a || (b == a && ib < ia);
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    float best = -1.0;
    uint index = NO_SHOOTER;
    float fallback = -1.0;
    uint fallback_at = NO_SHOOTER;
    vec4 reflected = vec4(0.0);
    vec4 emitted = vec4(0.0);
    float largest_importance = 0.0;
    for (uint s = lane; s < pc.surface_count; s += 256u) {
        vec4 st = stats[s];
        vec4 imp = importance_stats[s];
        float area = surfaces[s].axis_t_area.w;
        float power = pc.mode == SELECT_IMPORTANCE_SHOOTER ? imp.z : st.w;
        float priority = pc.mode == SELECT_IMPORTANCE_WEIGHTED ? imp.y * st.w : power;
        reflected += vec4(st.rgb * area, power);
        largest_importance = max(largest_importance, imp.y);
        if (emission_unshot[s] != 0u) emitted.rgb += surfaces[s].emission.rgb * area;
        if (beats(priority, s, best, index)) { best = priority; index = s; }
        if (beats(power, s, fallback, fallback_at)) { fallback = power; fallback_at = s; }
    }
    best_value[lane] = best;
    best_index[lane] = index;
    fallback_value[lane] = fallback;
    fallback_index[lane] = fallback_at;
    importance_max[lane] = largest_importance;
    reflected_sum[lane] = reflected;
    emitted_sum[lane] = emitted;
    barrier();
    for (uint stride = 128u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            uint other = lane + stride;
            if (beats(best_value[other], best_index[other], best_value[lane], best_index[lane])) {
                best_value[lane] = best_value[other];
                best_index[lane] = best_index[other];
            }
            if (beats(fallback_value[other], fallback_index[other], fallback_value[lane], fallback_index[lane])) {
                fallback_value[lane] = fallback_value[other];
                fallback_index[lane] = fallback_index[other];
            }
            importance_max[lane] = max(importance_max[lane], importance_max[other]);
            reflected_sum[lane] += reflected_sum[other];
            emitted_sum[lane] += emitted_sum[other];
        }
        barrier();
    }
    if (lane != 0u) return;
    float total = reflected_sum[0].w;
    float most = max(shot.power.y, total);
    bool shoots = fallback_index[0] != NO_SHOOTER && fallback_value[0] > 0.0
        && fallback_value[0] > pc.epsilon * most;
    bool weighted = pc.mode == SELECT_IMPORTANCE_WEIGHTED;
    float spent = weighted ? pc.epsilon * most * importance_max[0] : 0.0;
    uint chosen = best_value[0] > spent ? best_index[0] : fallback_index[0];
    if (pc.mode != SELECT_IMPORTANCE_SHOOTER) {
        vec3 r = pc.reflectance_sum.rgb;
        vec3 ambient = (r * reflected_sum[0].rgb + (r - 1.0) * emitted_sum[0].rgb) / pc.total_area;
        shot.ambient = vec4(ambient, 0.0);
    }
    float shooter_power = shoots ? stats[chosen].w : 0.0;
    if (pc.mode == SELECT_IMPORTANCE_SHOOTER && shoots) shooter_power = importance_stats[chosen].z;
    shot.power = vec4(total, most, shooter_power, shot.power.w + (shoots ? 1.0 : 0.0));
    if (shoots) {
        SurfaceRecord surface = surfaces[chosen];
        uint side = 1u << surface.grid.w;
        shot.shooter = chosen;
        shot.level = surface.grid.w;
        shot.blocks_x = (surface.grid.y + side - 1u) / side;
        shot.blocks_y = (surface.grid.z + side - 1u) / side;
    } else {
        shot.shooter = NO_SHOOTER;
        shot.blocks_x = 0u;
        shot.blocks_y = 0u;
    }
}
