#version 460
// The next table column to deliver (spec 004 §6.5): the first marked column; its location goes
// into slot 0 for the item buffer, and the count of marked columns into the shot state (the
// viewer's and the frame loop's "deliveries pending").
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = 256) in;

layout(binding = RAD_TABLE_COLUMNS, std430) readonly buffer Columns { uint columns[]; };
layout(binding = RAD_TABLE_LOCATIONS, std430) readonly buffer TableLocations { Location table_locations[]; };
layout(binding = RAD_LOCATIONS, std430) writeonly buffer Locations { Location locations[]; };
layout(binding = RAD_DELIVERY, std430) buffer DeliveryBuffer { Delivery delivery; };
layout(binding = RAD_SHOT, std430) buffer ShotBuffer { Shot shot; };

layout(push_constant) uniform Push {
    uint column_count;
} pc;

shared uint first[256];
shared uint count[256];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint found = NO_COLUMN;
    uint marked = 0u;
    for (uint c = lane; c < pc.column_count; c += 256u) {
        if (columns[c] != 0u) {
            found = min(found, c);
            marked++;
        }
    }
    first[lane] = found;
    count[lane] = marked;
    barrier();
    for (uint stride = 128u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            first[lane] = min(first[lane], first[lane + stride]);
            count[lane] += count[lane + stride];
        }
        barrier();
    }
    if (lane != 0u) return;
    uint column = first[0];
    delivery.column = column;
    delivery.pending = count[0];
    shot.table = uvec4(count[0], delivery.generation, 0u, 0u);
    if (column == NO_COLUMN) {
        locations[0].normal_kind = vec4(0.0, 0.0, 1.0, LOCATION_NONE);
    } else {
        locations[0] = table_locations[column];
    }
}
