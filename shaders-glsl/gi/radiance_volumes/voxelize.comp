#version 460
// Binary voxelisation (spec 001 §4.6), conservative, in compute: one thread per triangle marks
// every voxel its surface touches, column by column along its dominant axis (the column's
// square overlaps the projected triangle; the voxels between the plane's lowest and highest
// depth over the square, within the triangle's depth range). Mirrors voxels.rs
// `voxelize_triangle`; every mark writes the same 1, so the order of threads does not matter.
#include "common/scene.glsl"
#include "gi/radiance_volumes/voxel_column.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RV_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RV_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = RV_VOXEL_TARGET, std430) writeonly buffer Target { uint target[]; };

layout(push_constant) uniform Push {
    vec4 lo_voxel;      // the cube's minimum corner, a voxel's side
    uint resolution;
    uint triangle_count;
} pc;

void main() {
    // Triangles run along x and, past the dispatch limit of x, on along y.
    uint id = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (id >= pc.triangle_count) return;
    Triangle tri = triangles[id];
    vec3 corner[3];
    for (uint i = 0u; i < 3u; ++i) corner[i] = (vertices[tri[i]].position.xyz - pc.lo_voxel.xyz) / pc.lo_voxel.w;
    VoxelTriangle t;
    if (!voxel_triangle(corner, t)) return;
    float n = float(pc.resolution);
    vec2 lo = min(t.p[0], min(t.p[1], t.p[2]));
    vec2 hi = max(t.p[0], max(t.p[1], t.p[2]));
    if (hi.x < 0.0 || hi.y < 0.0 || lo.x >= n || lo.y >= n) return;
    uvec2 first = uvec2(max(floor(lo), vec2(0.0)));
    uvec2 last = uvec2(min(floor(hi), vec2(n - 1.0)));
    for (uint j = first.y; j <= last.y; ++j) {
        for (uint i = first.x; i <= last.x; ++i) {
            uvec2 column = uvec2(i, j);
            uint k0;
            uint k1;
            if (!voxel_column_overlaps(t, column) || !voxel_column_range(t, column, pc.resolution, k0, k1)) continue;
            for (uint k = k0; k <= k1; ++k) target[voxel_column_index(t, column, k, pc.resolution)] = 1u;
        }
    }
}
