#version 460
// Cache lighting (spec 001 §4.4): one thread per cache held, dispatched indirectly. Every VAL of
// every light view sends the cache its perpendicular irradiance Φ/π · max(0, n·(-ω)) / (r² + A)
// from direction ω, projected as a delta lobe onto 2 or 3 SH bands. VALs are loaded into shared
// memory RV_LIGHT_GROUP at a time, each thread then reads all of them.
#include "common/math.glsl"
#include "gi/shared/sh.glsl"
#include "gi/radiance_volumes/state.glsl"
#include "gi/radiance_volumes/val.glsl"

layout(local_size_x = RV_LIGHT_GROUP) in;

layout(binding = RV_CACHES, std430) buffer Caches { vec4 caches[]; };
layout(binding = RV_VALS, std430) readonly buffer Vals { Val vals[]; };
layout(binding = RV_STATE, std430) readonly buffer State { RvState state; };

layout(push_constant) uniform Push {
    uint capacity;
    uint stride;
    uint coefficients;  // 4 (L1) or 9 (L2)
    uint val_count;     // VALs of the read level, all layers
} pc;

shared vec4 shared_position_area[RV_LIGHT_GROUP];
shared vec4 shared_normal[RV_LIGHT_GROUP];  // w: 1 for a VAL that sent light, 0 otherwise
shared vec3 shared_flux[RV_LIGHT_GROUP];    // flux / pi

void main() {
    uint held = min(state.requested, pc.capacity);
    uint index = gl_GlobalInvocationID.x;
    uint local = gl_LocalInvocationID.x;
    bool holds_cache = index < held;
    vec3 x = holds_cache ? caches[index * pc.stride].xyz : vec3(0.0);
    vec3 c[SH_L2_COEFFICIENTS];
    for (uint i = 0u; i < SH_L2_COEFFICIENTS; ++i) c[i] = vec3(0.0);
    for (uint base = 0u; base < pc.val_count; base += RV_LIGHT_GROUP) {
        uint j = base + local;
        vec4 normal = vec4(0.0);
        if (j < pc.val_count) {
            Val v = vals[j];
            float len = length(v.normal_area.xyz);
            bool lit = v.position_texels.w > 0.0 && len > 0.0;
            shared_position_area[local] = vec4(v.position_texels.xyz, v.normal_area.w);
            shared_flux[local] = v.flux_depth.rgb * INV_PI;
            normal = lit ? vec4(v.normal_area.xyz / len, 1.0) : vec4(0.0);
        }
        shared_normal[local] = normal;
        barrier();
        if (holds_cache) {
            uint batch = min(RV_LIGHT_GROUP, pc.val_count - base);
            for (uint t = 0u; t < batch; ++t) {
                vec4 n = shared_normal[t];
                if (n.w == 0.0) continue;
                vec4 pa = shared_position_area[t];
                vec3 to = pa.xyz - x;
                float r2 = dot(to, to);
                if (r2 == 0.0) continue;
                vec3 w = to * inversesqrt(r2);
                float cos_val = dot(n.xyz, -w);
                if (cos_val <= 0.0) continue;
                vec3 e = shared_flux[t] * (cos_val / (r2 + pa.w));
                float y[SH_L2_COEFFICIENTS];
                sh_l2_basis(w, y);
                for (uint i = 0u; i < pc.coefficients; ++i) c[i] += e * y[i];
            }
        }
        barrier();
    }
    if (!holds_cache) return;
    for (uint i = 0u; i < pc.coefficients; ++i) caches[index * pc.stride + 1u + i] = vec4(c[i], 0.0);
}
