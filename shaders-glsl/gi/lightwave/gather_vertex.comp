#version 460
// LightWave per vertex (the thesis's Gouraud shading, spec 002 §2.4): each pixel's gather is
// interpolated from its triangle's corners (vertex_gather.comp), with the barycentric weights
// of the pixel's G-buffer position in the triangle that triangle_ids.frag saw there; the side
// (front or back value) follows the G-buffer normal, which faces the camera.
#include "gi/lightwave/composite.glsl"
#include "common/scene.glsl"

layout(binding = GATHER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = GATHER_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = GATHER_VERTEX_NORMALS, std430) readonly buffer Normals { vec4 normals[]; };
layout(binding = GATHER_VERTEX_VALUES, std430) readonly buffer Values { vec2 values[]; };
layout(binding = GATHER_TRIANGLE_IDS, r32ui) readonly uniform uimage2D triangle_ids;

// The weights of p's projection onto triangle (a, b, c) (a third each if it is degenerate).
vec3 barycentric(vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 e1 = b - a, e2 = c - a, d = p - a;
    float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    float d1 = dot(d, e1), d2 = dot(d, e2);
    float det = d11 * d22 - d12 * d12;
    if (!(det > 1e-30 * d11 * d22)) return vec3(1.0 / 3.0);
    float v = (d22 * d1 - d12 * d2) / det;
    float w = (d11 * d2 - d12 * d1) / det;
    return vec3(1.0 - v - w, v, w);
}

// The pixel's triangle (0: none), its corners, their weights, and which side of the corners'
// gather normals the G-buffer normal faces.
uint triangle_id;
uvec3 corners;
vec3 weights;
bool front;

void prepare_gather(ivec2 pixel, vec3 p, vec3 n) {
    triangle_id = imageLoad(triangle_ids, pixel).x;
    if (triangle_id == 0u) return;
    corners = triangles[triangle_id - 1u].xyz;
    weights = barycentric(p, vertices[corners.x].position.xyz, vertices[corners.y].position.xyz,
                          vertices[corners.z].position.xyz);
    vec3 normal = weights.x * normals[corners.x].xyz + weights.y * normals[corners.y].xyz
                + weights.z * normals[corners.z].xyz;
    front = dot(normal, n) >= 0.0;
}

float gathered(uint l, vec3 p, vec3 n) {
    // A pixel the G-buffer covers and this raster missed (none, with the same geometry).
    if (triangle_id == 0u) return gather(l, p, n);
    vec3 value;
    for (int k = 0; k < 3; ++k) {
        vec2 front_back = values[corners[k] * LIGHT_COUNT + l];
        value[k] = front ? front_back.x : front_back.y;
    }
    return dot(weights, value);
}
