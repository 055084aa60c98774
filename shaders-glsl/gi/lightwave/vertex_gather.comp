#version 460
// LightWave's per-vertex gather (the thesis's vertex shader, spec 002 §2.4): the indirect term
// of every light at every vertex, for its gather normal and the opposite one (vkgi's surfaces
// are two-sided; the thesis's were seen from one side). gather_vertex.comp interpolates them
// across each triangle. One workgroup per (vertex, light): its invocations split the VPLs and
// add their partial sums in shared memory, so a mesh of few vertices still fills the device.
#include "common/scene.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = VERTEX_GATHER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
// Per vertex: xyz the unit normal the gather uses (see cpu.rs `gather_normals`).
layout(binding = VERTEX_GATHER_NORMALS, std430) readonly buffer Normals { vec4 normals[]; };
layout(binding = VERTEX_GATHER_VPLS, std430) readonly buffer Vpls { vec4 vpls[]; };
// Per vertex, per light: (front, back).
layout(binding = VERTEX_GATHER_OUT, std430) writeonly buffer Values { vec2 values[]; };

layout(push_constant) uniform Push {
    uint vertex_count;
    uint light_count;
    uint per_light;
} pc;

#include "gi/lightwave/rig_gather.glsl"

shared vec2 partial[LINEAR_WORKGROUP];

void main() {
    // Workgroups run in rows of at most 65535 (the smallest limit a device may have).
    uint i = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (i >= pc.vertex_count * pc.light_count) return;   // the whole workgroup
    uint lane = gl_LocalInvocationID.x;
    uint vertex = i / pc.light_count;
    uint first = (i % pc.light_count) * pc.per_light;
    vec3 p = vertices[vertex].position.xyz;
    vec3 n = normals[vertex].xyz;
    partial[lane] = vec2(rig_gather_part(first, pc.per_light, lane, LINEAR_WORKGROUP, p, n),
                         rig_gather_part(first, pc.per_light, lane, LINEAR_WORKGROUP, p, -n));
    barrier();
    for (uint half_width = LINEAR_WORKGROUP / 2u; half_width > 0u; half_width /= 2u) {
        if (lane < half_width) partial[lane] += partial[lane + half_width];
        barrier();
    }
    if (lane == 0u) values[i] = partial[0] / float(pc.per_light);
}
