#version 460
// One voxel column of one triangle (see voxelize_raster.vert): the column's square must overlap
// the projected triangle (the rasteriser overestimates; the exact test, bounding box and edges,
// then keeps only the compute voxelisation's columns), and the voxels between the plane's lowest
// and highest depth over the square, within the triangle's depth range, are marked.
#include "common/scene.glsl"
#include "gi/radiance_volumes/voxel_column.glsl"

layout(binding = RV_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RV_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = RV_VOXEL_TARGET, std430) writeonly buffer Target { uint target[]; };

layout(push_constant) uniform Push {
    vec4 lo_voxel;
    uint resolution;
} pc;

layout(location = 0) flat in uint in_triangle;
layout(location = 0) out vec4 out_coverage;

void main() {
    out_coverage = vec4(1.0);
    Triangle tri = triangles[in_triangle];
    vec3 corner[3];
    for (uint i = 0u; i < 3u; ++i) corner[i] = (vertices[tri[i]].position.xyz - pc.lo_voxel.xyz) / pc.lo_voxel.w;
    VoxelTriangle t;
    if (!voxel_triangle(corner, t)) return;
    uvec2 column = uvec2(gl_FragCoord.xy);
    uint k0;
    uint k1;
    if (!voxel_column_in_box(t, column, pc.resolution) || !voxel_column_overlaps(t, column)
        || !voxel_column_range(t, column, pc.resolution, k0, k1)) return;
    for (uint k = k0; k <= k1; ++k) target[voxel_column_index(t, column, k, pc.resolution)] = 1u;
}
