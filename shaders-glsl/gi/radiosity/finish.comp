#version 460
// The shooter has shot from every location: its unshot radiosity and emission are gone.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { Surface surfaces[]; };
layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
layout(binding = RAD_UNSHOT, std430) buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) buffer EmissionUnshot { uint emission_unshot[]; };

void main() {
    if (shot.shooter == NO_SHOOTER) return;
    uvec4 grid = surfaces[shot.shooter].grid;
    uint i = gl_GlobalInvocationID.x;
    if (i == 0u) emission_unshot[shot.shooter] = 0u;
    if (i < grid.y * grid.z) unshot[grid.x + i] = vec4(0.0);
}
