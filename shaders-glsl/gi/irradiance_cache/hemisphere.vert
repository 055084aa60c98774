#version 460
// GPU hemisphere sampling (spec 003 §6, §17): the scene seen from a record this round added, by
// a perspective camera on the record looking along its normal with tan(fov/2) = 2 (126.87°),
// its x along the basis's tangent and y along the bitangent (src/gi/irradiance_cache/tables.rs).
// Slots past the round's records draw nothing (draws.glsl).
#include "common/scene.glsl"
#include "common/sampling.glsl"
#include "gi/irradiance_cache/ic.glsl"

layout(binding = IC_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = IC_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = IC_RECORDS, std430) readonly buffer Records { Record records[]; };
layout(binding = IC_STATE, std430) readonly buffer State { CacheState state; };

layout(push_constant) uniform Push {
    uint slot;
    float near;   // the camera sits this far above the record, and clips this close
    float far;
    float half_width;
    uint light_count;
    float accuracy;       // the snapshot's weighting (bounces past the first)
    float smooth_weight;
    float normal_factor;
} pc;

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) flat out vec3 out_face_normal;
layout(location = 3) flat out uint out_material;
layout(location = 4) out vec2 out_texcoord;
layout(location = 5) flat out vec3 out_eye;

void main() {
    Record record = records[state.first + pc.slot];
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
    vec3 n = record.normal_footprint.xyz;
    vec3 eye = record.position_harmonic.xyz + n * pc.near;
    out_eye = eye;
    vec3 t, s;
    orthonormal_basis(n, t, s);
    vec3 v = p - eye;
    float z = dot(v, n);
    gl_Position = vec4(dot(v, t) / pc.half_width, dot(v, s) / pc.half_width,
                       (z - pc.near) * pc.far / (pc.far - pc.near), z);
}
