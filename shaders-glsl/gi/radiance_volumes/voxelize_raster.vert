#version 460
// The binary voxelisation by conservative rasterisation (spec 001 §4.6, the public code's
// path): every triangle drawn onto the face of the voxel cube across its dominant axis, one
// pixel per voxel column; voxelize_raster.frag marks the column's voxels. Vertex pulling, no
// vertex input.
#include "common/scene.glsl"
#include "gi/radiance_volumes/voxel_column.glsl"

layout(binding = RV_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RV_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };

layout(push_constant) uniform Push {
    vec4 lo_voxel;      // the cube's minimum corner, a voxel's side
    uint resolution;
} pc;

layout(location = 0) flat out uint out_triangle;

void main() {
    uint id = gl_VertexIndex / 3u;
    Triangle tri = triangles[id];
    vec3 corner[3];
    for (uint i = 0u; i < 3u; ++i) corner[i] = (vertices[tri[i]].position.xyz - pc.lo_voxel.xyz) / pc.lo_voxel.w;
    VoxelTriangle t;
    out_triangle = id;
    if (!voxel_triangle(corner, t)) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);  // degenerate: nothing drawn
        return;
    }
    // The viewport is resolution² pixels: pixel (i, j) is column (i, j).
    gl_Position = vec4(t.p[gl_VertexIndex % 3u] / float(pc.resolution) * 2.0 - 1.0, 0.5, 1.0);
}
