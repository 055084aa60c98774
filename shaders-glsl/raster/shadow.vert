#version 460
// Depth-only rendering of the scene from one shadow view (vertex pulling, no vertex input).
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RASTER_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
} pc;

void main() {
    uint corner = triangles[gl_VertexIndex / 3][gl_VertexIndex % 3];
    gl_Position = pc.view_projection * vec4(vertices[corner].position.xyz, 1.0);
}
