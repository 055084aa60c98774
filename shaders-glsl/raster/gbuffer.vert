#version 460
// G-buffer geometry: pulls its triangle's corners, passes world position, shading normal, the
// geometric normal (for facing) and the material.
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RASTER_TRIANGLE_MATERIALS, std430) readonly buffer TriangleMaterials { uint triangle_materials[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 camera_position;
} pc;

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) flat out vec3 out_face_normal;
layout(location = 3) flat out uint out_material;

void main() {
    int triangle = gl_VertexIndex / 3;
    vec3 a = vertices[3 * triangle].position.xyz;
    vec3 b = vertices[3 * triangle + 1].position.xyz;
    vec3 c = vertices[3 * triangle + 2].position.xyz;
    vec3 p = vertices[gl_VertexIndex].position.xyz;
    out_position = p;
    out_normal = vertices[gl_VertexIndex].normal.xyz;
    out_face_normal = normalize(cross(b - a, c - a));
    out_material = triangle_materials[triangle];
    gl_Position = pc.view_projection * vec4(p, 1.0);
}
