#version 460
// LightWave's per-vertex gather (the thesis's vertex shader, spec 002 §2.4): the indirect term
// of every light at every vertex, for its gather normal and the opposite one (vkgi's surfaces
// are two-sided; the thesis's were seen from one side). gather_vertex.comp interpolates them
// across each triangle.
//
// A workgroup takes LINEAR_WORKGROUP / slices (vertex, light) pairs and splits each pair's VPLs
// into `slices` (a power of two, src/gi/lightwave/vertex.rs): invocation `lane` gathers pair
// lane % pairs_per_group over every slices-th VPL from slice lane / pairs_per_group, and the
// slices' partial sums are added in shared memory. Few pairs (a small mesh) get many slices, so
// the device still fills; many pairs get one, so neighbouring invocations read the same VPL.
#include "common/scene.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = VERTEX_GATHER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
// Per vertex: xyz the unit normal the gather uses (see cpu.rs `gather_normals`).
layout(binding = VERTEX_GATHER_NORMALS, std430) readonly buffer Normals { vec4 normals[]; };
layout(binding = VERTEX_GATHER_VPLS) uniform samplerBuffer vpls;
// Per vertex, per light: (front, back).
layout(binding = VERTEX_GATHER_OUT, std430) writeonly buffer Values { vec2 values[]; };

layout(push_constant) uniform Push {
    uint vertex_count;
    uint light_count;
    uint per_light;
    uint slices;   // a power of two, at most LINEAR_WORKGROUP
} pc;

#include "gi/lightwave/rig_gather.glsl"

shared vec2 partial[LINEAR_WORKGROUP];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint pairs_per_group = LINEAR_WORKGROUP / pc.slices;
    // Workgroups run in rows of at most 65535 (the smallest limit a device may have).
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint i = group * pairs_per_group + lane % pairs_per_group;
    uint slice = lane / pairs_per_group;
    vec2 sum = vec2(0.0);
    if (i < pc.vertex_count * pc.light_count) {
        uint vertex = i / pc.light_count;
        uint first = (i % pc.light_count) * pc.per_light;
        vec3 p = vertices[vertex].position.xyz;
        vec3 n = normals[vertex].xyz;
        sum = vec2(rig_gather_part(first, pc.per_light, slice, pc.slices, p, n),
                   rig_gather_part(first, pc.per_light, slice, pc.slices, p, -n));
    }
    partial[lane] = sum;
    barrier();
    // Lanes lane and lane + half_width hold the same pair while half_width >= pairs_per_group.
    for (uint half_width = LINEAR_WORKGROUP / 2u; half_width >= pairs_per_group; half_width /= 2u) {
        if (lane < half_width) partial[lane] += partial[lane + half_width];
        barrier();
    }
    if (slice == 0u && i < pc.vertex_count * pc.light_count) {
        values[i] = partial[lane] / float(pc.per_light);
    }
}
