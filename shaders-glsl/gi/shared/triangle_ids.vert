#version 460
// The triangle each pixel sees (for methods that look their triangle up): the G-buffer's geometry (same
// corners, same transform), with the triangle's index passed on.
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RASTER_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
} pc;

layout(location = 0) flat out uint out_triangle;

void main() {
    Triangle triangle = triangles[gl_VertexIndex / 3];
    uint corner = triangle[gl_VertexIndex % 3];
    vec3 p = vertices[corner].position.xyz;
    out_triangle = gl_VertexIndex / 3;
    gl_Position = pc.view_projection * vec4(p, 1.0);
}
