#version 460
// LightWave's rig (seed 002 eqs 4.1-4.2, spec 002 §2.2): per light, VPLs on shells around it,
// opening along its axis. One invocation per VPL; src/gi/lightwave/rig.rs is the f64 definition
// (same order: pole ray first, then azimuth-major, tilt, shell).
#include "common/lights.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = VPLS_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
// Two vec4 per VPL: (position, weight), (direction, light index).
layout(binding = VPLS_OUT, std430) writeonly buffer Vpls { vec4 vpls[]; };

layout(push_constant) uniform Push {
    uint angle_deg;
    uint per_ray;
    float radius;
    uint per_light;
    uint light_count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.per_light * pc.light_count) return;
    uint l = i / pc.per_light;
    uint j = i % pc.per_light;
    uint ray = j / pc.per_ray;
    uint k = j % pc.per_ray;
    uint tilts = 90u / pc.angle_deg;
    float tilt = 0.0;
    float azimuth = 0.0;
    if (ray > 0u) {
        tilt = radians(float(pc.angle_deg * ((ray - 1u) % tilts + 1u)));
        azimuth = radians(float(pc.angle_deg * ((ray - 1u) / tilts)));
    }
    Light light = lights[l];
    vec3 axis = normalize(light.direction_cos_outer.xyz);
    vec3 u, v;
    light_frame(axis, u, v);
    // rig.rs's w is -v: a light looking down gets (sin t cos a, -cos t, -sin t sin a).
    vec3 direction = axis * cos(tilt) + (u * cos(azimuth) - v * sin(azimuth)) * sin(tilt);
    float distance = pc.radius * (1.0 - exp2(-float(k + 1u)));
    float weight = 1.0 - 0.05 * exp2(float(k));
    vpls[2u * i] = vec4(light.position_kind.xyz + direction * distance, weight);
    vpls[2u * i + 1u] = vec4(direction, float(l));
}
