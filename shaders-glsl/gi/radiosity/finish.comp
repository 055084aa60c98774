#version 460
// The shooter has shot from every location: its unshot radiosity and emission (or, after an
// importance shot, its unshot importance) are gone.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { SurfaceRecord surfaces[]; };
layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
layout(binding = RAD_UNSHOT, std430) buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_IMPORTANCE_UNSHOT, std430) buffer ImportanceUnshot { float importance_unshot[]; };

layout(push_constant) uniform Push {
    uint quantity;   // QUANTITY_*
} pc;

void main() {
    if (shot.shooter == NO_SHOOTER) return;
    uvec4 grid = surfaces[shot.shooter].grid;
    uint i = gl_GlobalInvocationID.x;
    if (pc.quantity == QUANTITY_IMPORTANCE) {
        if (i < grid.y * grid.z) importance_unshot[grid.x + i] = 0.0;
        return;
    }
    if (i == 0u) emission_unshot[shot.shooter] = 0u;
    if (i < grid.y * grid.z) unshot[grid.x + i] = vec4(0.0);
}
