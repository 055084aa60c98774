#version 460
// After the simulated view changes (spec 004 §6.4): mark each table column that holds an entry
// for a receiver now in view. One thread per (receiver, column); the flags start cleared.
#include "gi/radiosity/radiosity.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_VISIBLE, std430) readonly buffer Visible { uint visible[]; };
layout(binding = RAD_TABLE, std430) readonly buffer Table { TableEntry table[]; };
layout(binding = RAD_TABLE_COLUMNS, std430) writeonly buffer Columns { uint columns[]; };

layout(push_constant) uniform Push {
    uint surface_count;
    uint column_count;
} pc;

void main() {
    uint j = gl_GlobalInvocationID.x;
    uint column = gl_GlobalInvocationID.y;
    if (j >= pc.surface_count || column >= pc.column_count || visible[j] == 0u) return;
    TableEntry entry = table[column * pc.surface_count + j];
    if (entry.emitted.rgb != vec3(0.0) || entry.reflected.rgb != vec3(0.0)) columns[column] = 1u;
}
