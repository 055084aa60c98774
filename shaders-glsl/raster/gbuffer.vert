#version 460
// G-buffer geometry: pulls its triangle's corners through the triangle's vertex indices, passes
// world position, interpolated vertex normal, the geometric normal (for facing and where the
// vertices have no normals), texture coordinates and the material.
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RASTER_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 camera_position;
} pc;

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) flat out vec3 out_face_normal;
layout(location = 3) flat out uint out_material;
layout(location = 4) out vec2 out_texcoord;

void main() {
    Triangle triangle = triangles[gl_VertexIndex / 3];
    uint corner = triangle[gl_VertexIndex % 3];
    vec3 a = vertices[triangle.x].position.xyz;
    vec3 b = vertices[triangle.y].position.xyz;
    vec3 c = vertices[triangle.z].position.xyz;
    vec3 p = vertices[corner].position.xyz;
    out_position = p;
    out_normal = vertices[corner].normal.xyz;
    out_face_normal = normalize(cross(b - a, c - a));
    out_material = triangle.w;
    out_texcoord = vertex_texcoord(vertices[corner]);
    gl_Position = pc.view_projection * vec4(p, 1.0);
}
