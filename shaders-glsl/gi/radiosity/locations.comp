#version 460
// The shooting locations of the selected surface (spec 004 pass A2): block k of 2^level x
// 2^level texels becomes one disc at the area-weighted centroid, with the block's area and its
// mean unshot radiosity (the mip-n texel of the thesis, without NPOT mip bias). One workgroup
// per location slot; slots past the surface's blocks are left empty. An importance shot's
// locations carry the block's mean unshot importance in `reflected.x` and nothing emitted.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { SurfaceRecord surfaces[]; };
layout(binding = RAD_ELEMENTS, std430) readonly buffer Elements { Element elements[]; };
layout(binding = RAD_UNSHOT, std430) readonly buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_EMISSION_UNSHOT, std430) readonly buffer EmissionUnshot { uint emission_unshot[]; };
layout(binding = RAD_IMPORTANCE_UNSHOT, std430) readonly buffer ImportanceUnshot { float importance_unshot[]; };
layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
layout(binding = RAD_LOCATIONS, std430) writeonly buffer Locations { Location locations[]; };

layout(push_constant) uniform Push {
    uint quantity;   // QUANTITY_*
} pc;

shared vec4 position_sum[LINEAR_WORKGROUP];
shared vec4 unshot_sum[LINEAR_WORKGROUP];

void main() {
    uint slot = gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationID.x;
    bool shooting = shot.shooter != NO_SHOOTER && slot < shot.blocks_x * shot.blocks_y;
    vec4 p = vec4(0.0);
    vec4 u = vec4(0.0);
    SurfaceRecord surface;
    if (shooting) {
        surface = surfaces[shot.shooter];
        uint side = 1u << shot.level;
        uvec2 block = uvec2(slot % shot.blocks_x, slot / shot.blocks_x) * side;
        for (uint i = lane; i < side * side; i += LINEAR_WORKGROUP) {
            uvec2 texel = block + uvec2(i % side, i / side);
            if (texel.x >= surface.grid.y || texel.y >= surface.grid.z) continue;
            uint e = surface.grid.x + texel.y * surface.grid.y + texel.x;
            float area = elements[e].position_area.w;
            p += vec4(elements[e].position_area.xyz * area, area);
            u += pc.quantity == QUANTITY_IMPORTANCE
                ? vec4(importance_unshot[e] * area, 0.0, 0.0, 0.0)
                : vec4(unshot[e].rgb * area, 0.0);
        }
    }
    position_sum[lane] = p;
    unshot_sum[lane] = u;
    barrier();
    for (uint stride = LINEAR_WORKGROUP / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            position_sum[lane] += position_sum[lane + stride];
            unshot_sum[lane] += unshot_sum[lane + stride];
        }
        barrier();
    }
    if (lane != 0u) return;
    float area = position_sum[0].w;
    Location location;
    if (!shooting || area <= 0.0) {
        location.position_area = vec4(0.0);
        location.normal_kind = vec4(0.0, 0.0, 1.0, LOCATION_NONE);
        location.emitted = vec4(0.0);
        location.reflected = vec4(0.0);
    } else {
        bool emits = pc.quantity == QUANTITY_RADIOSITY && emission_unshot[shot.shooter] != 0u;
        location.position_area = vec4(position_sum[0].xyz / area, area);
        location.normal_kind = vec4(surface.normal.xyz, LOCATION_SURFACE);
        location.emitted = vec4(emits ? surface.emission.rgb : vec3(0.0), 0.0);
        location.reflected = vec4(unshot_sum[0].rgb / area, 0.0);
    }
    locations[slot] = location;
}
