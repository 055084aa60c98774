#version 460
// The next shooter: the surface of most unshot power (spec 004 pass A1, a reduction instead of
// the thesis's 1-pixel depth test), the ambient term still to arrive (§4.1.6, split so the
// direct part the rasteriser already draws is not counted twice), and the convergence test.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = 256) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { Surface surfaces[]; };
layout(binding = RAD_STATS, std430) readonly buffer Stats { vec4 stats[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) readonly buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_SHOT, std430) buffer ShotBuffer { Shot shot; };

layout(push_constant) uniform Push {
    vec4 reflectance_sum;  // rgb 1 / (1 - mean albedo): every bounce of the ambient term
    uint surface_count;
    float total_area;
    float epsilon;         // converged below this fraction of the most unshot power
} pc;

shared float best_power[256];
shared uint best_index[256];
shared vec4 reflected_sum[256];
shared vec4 emitted_sum[256];

void main() {
    uint lane = gl_LocalInvocationID.x;
    float best = -1.0;
    uint index = NO_SHOOTER;
    vec4 reflected = vec4(0.0);
    vec4 emitted = vec4(0.0);
    for (uint s = lane; s < pc.surface_count; s += 256u) {
        vec4 st = stats[s];
        float area = surfaces[s].axis_t_area.w;
        reflected += vec4(st.rgb * area, st.w);
        if (emission_unshot[s] != 0u) emitted.rgb += surfaces[s].emission.rgb * area;
        if (st.w > best) { best = st.w; index = s; }
    }
    best_power[lane] = best;
    best_index[lane] = index;
    reflected_sum[lane] = reflected;
    emitted_sum[lane] = emitted;
    barrier();
    for (uint stride = 128u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            uint other = lane + stride;
            bool wins = best_power[other] > best_power[lane]
                || (best_power[other] == best_power[lane] && best_index[other] < best_index[lane]);
            if (wins) {
                best_power[lane] = best_power[other];
                best_index[lane] = best_index[other];
            }
            reflected_sum[lane] += reflected_sum[other];
            emitted_sum[lane] += emitted_sum[other];
        }
        barrier();
    }
    if (lane != 0u) return;
    float total = reflected_sum[0].w;
    float most = max(shot.power.y, total);
    bool shoots = best_index[0] != NO_SHOOTER && best_power[0] > 0.0
        && best_power[0] > pc.epsilon * most;
    vec3 r = pc.reflectance_sum.rgb;
    vec3 ambient = (r * reflected_sum[0].rgb + (r - 1.0) * emitted_sum[0].rgb) / pc.total_area;
    shot.ambient = vec4(ambient, 0.0);
    shot.power = vec4(total, most, shoots ? best_power[0] : 0.0, shot.power.w + (shoots ? 1.0 : 0.0));
    if (shoots) {
        Surface surface = surfaces[best_index[0]];
        uint side = 1u << surface.grid.w;
        shot.shooter = best_index[0];
        shot.level = surface.grid.w;
        shot.blocks_x = (surface.grid.y + side - 1u) / side;
        shot.blocks_y = (surface.grid.z + side - 1u) / side;
    } else {
        shot.shooter = NO_SHOOTER;
        shot.blocks_x = 0u;
        shot.blocks_y = 0u;
    }
}
