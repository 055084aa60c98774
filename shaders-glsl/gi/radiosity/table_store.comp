#version 460
// pd's gather into the stored radiosity table (spec 004 §6.3): every shooting location of the
// current shot adds its unshot radiosity to the entry of each receiver surface out of the
// simulated view (no form factor yet: visibility and distance are resolved when the entry is
// delivered), and records itself as its column's location. One thread per (receiver, slot).
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
layout(binding = RAD_LOCATIONS, std430) readonly buffer Locations { Location locations[]; };
layout(binding = RAD_VISIBLE, std430) readonly buffer Visible { uint visible[]; };
layout(binding = RAD_TABLE, std430) buffer Table { TableEntry table[]; };
layout(binding = RAD_TABLE_LOCATIONS, std430) writeonly buffer TableLocations { Location table_locations[]; };

layout(push_constant) uniform Push {
    uint surface_count;
    uint slots;
} pc;

void main() {
    uint j = gl_GlobalInvocationID.x;
    uint slot = gl_GlobalInvocationID.y;
    if (j >= pc.surface_count || slot >= pc.slots || shot.shooter == NO_SHOOTER) return;
    Location location = locations[slot];
    if (location.normal_kind.w != LOCATION_SURFACE) return;
    uint column = shot.shooter * pc.slots + slot;
    if (j == 0u) table_locations[column] = location;
    if (visible[j] != 0u || j == shot.shooter) return;
    uint at = column * pc.surface_count + j;
    table[at].emitted.rgb += location.emitted.rgb;
    table[at].reflected.rgb += location.reflected.rgb;
}
