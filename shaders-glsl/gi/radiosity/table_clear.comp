#version 460
// The delivered column's entries for receivers in view are spent, and the column unmarked.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_VISIBLE, std430) readonly buffer Visible { uint visible[]; };
layout(binding = RAD_DELIVERY, std430) readonly buffer DeliveryBuffer { Delivery delivery; };
layout(binding = RAD_TABLE, std430) buffer Table { TableEntry table[]; };
layout(binding = RAD_TABLE_COLUMNS, std430) buffer Columns { uint columns[]; };

layout(push_constant) uniform Push {
    uint surface_count;
} pc;

void main() {
    uint j = gl_GlobalInvocationID.x;
    uint column = delivery.column;
    if (j >= pc.surface_count || column == NO_COLUMN) return;
    if (j == 0u) columns[column] = 0u;
    if (visible[j] != 0u) {
        table[column * pc.surface_count + j].emitted = vec4(0.0);
        table[column * pc.surface_count + j].reflected = vec4(0.0);
    }
}
