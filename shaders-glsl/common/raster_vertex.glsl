#ifndef VKGI_RASTER_VERTEX_GLSL
#define VKGI_RASTER_VERTEX_GLSL
// The vertex stage of the G-buffer and of the reflective shadow maps: pulls its triangle's
// corners through the triangle's vertex indices and passes world position, interpolated vertex
// normal, the geometric normal (for facing and where the vertices have no normals), texture
// coordinates and the material's albedo; with GBUFFER_EYE the eye, with MATERIAL_TERMS the
// material's emission and glossy lobe.
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RASTER_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = RASTER_MATERIALS, std430) readonly buffer Materials { Material materials[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 camera_position;
} pc;

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) flat out vec3 out_face_normal;
layout(location = 3) out vec2 out_texcoord;
// The triangle's material, read here once per corner rather than once per fragment: its
// albedo, and for the G-buffer its emission and glossy lobe.
layout(location = 4) flat out vec4 out_albedo;
#ifdef MATERIAL_TERMS
layout(location = 5) flat out vec4 out_emission;
layout(location = 6) flat out vec4 out_specular;
#endif
#ifdef GBUFFER_EYE
// The eye, which the G-buffer's fragments turn normals toward: a fragment shader reads push
// constants lane by lane on lavapipe (docs/performance.md).
layout(location = 7) flat out vec3 out_camera;
#endif

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
    Material m = materials[triangle.w];
    out_albedo = m.albedo;
#ifdef MATERIAL_TERMS
    out_emission = m.emission;
    out_specular = m.specular;
#endif
#ifdef GBUFFER_EYE
    out_camera = pc.camera_position.xyz;
#endif
    out_texcoord = vertex_texcoord(vertices[corner]);
    gl_Position = pc.view_projection * vec4(p, 1.0);
}

#endif
