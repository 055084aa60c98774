#version 460
// The hemisphere item buffer of one shooting location (spec 004 pass A3): the subdivided
// item-buffer mesh seen from the location, by the thesis's stereographic projection in one pass
// (face 0 of layer 0), or as one face of a hemicube. Each triangle carries the surface (side of
// its patch) that faces the location; the horizon is a clip plane. In camera mode (id, pd) it is
// the user's camera (or its wider simulated field of view) instead, through `camera`.
#include "gi/radiosity/radiosity.glsl"

layout(binding = RAD_LOCATIONS, std430) readonly buffer Locations { Location locations[]; };
// The mesh's vertices (three a triangle) and each triangle's sides, as texels: lavapipe fetches
// texels for all the lanes of a SIMD batch at once, where it reads a storage buffer at a vertex's
// index lane by lane (docs/radiosity.md).
layout(binding = RAD_ITEM_VERTICES) uniform samplerBuffer item_vertices;
layout(binding = RAD_ITEM_TRIANGLES) uniform usamplerBuffer item_triangles;

#define ITEM_STEREOGRAPHIC 0u
#define ITEM_HEMICUBE 1u
#define ITEM_CAMERA 2u

layout(push_constant) uniform Push {
    mat4 camera;     // camera mode: world to clip
    vec4 eye;        // camera mode: xyz
    uint slot;
    uint face;       // hemicube face 0-4
    uint projection; // ITEM_*
    float far;       // distances are stored as distance / far in depth
} pc;

layout(location = 0) flat out uint out_surface;
layout(location = 1) out float out_distance;

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[1];
};

void main() {
    Location location = locations[pc.slot];
    uint triangle = gl_VertexIndex / 3u;
    vec3 p = texelFetch(item_vertices, gl_VertexIndex).xyz;
    if (pc.projection == ITEM_CAMERA) {
        location.position_area = vec4(pc.eye.xyz, 0.0);
        location.normal_kind.w = LOCATION_SURFACE;
    }
    if (location.normal_kind.w == LOCATION_NONE) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        gl_ClipDistance[0] = -1.0;
        out_surface = 0u;
        out_distance = 0.0;
        return;
    }
    vec3 s = location.position_area.xyz;
    vec3 n = location.normal_kind.xyz;
    vec3 a = texelFetch(item_vertices, int(triangle * 3u)).xyz;
    vec3 face_normal = cross(texelFetch(item_vertices, int(triangle * 3u + 1u)).xyz - a,
                             texelFetch(item_vertices, int(triangle * 3u + 2u)).xyz - a);
    uvec4 sides = texelFetch(item_triangles, int(triangle));
    out_surface = dot(face_normal, s - a) >= 0.0 ? sides.x : sides.y;
    vec3 v = p - s;
    float r = length(v);
    out_distance = r;
    if (pc.projection == ITEM_CAMERA) {
        gl_ClipDistance[0] = 1.0;
        gl_Position = pc.camera * vec4(p, 1.0);
        return;
    }
    vec3 t, b;
    orthonormal_basis(n, t, b);
    // Slightly above the horizon, so the shooter's own polygon (coplanar, within rounding) is
    // never drawn over everything it sees.
    gl_ClipDistance[0] = dot(v, n) - pc.far * 1e-6;
    if (pc.projection == ITEM_STEREOGRAPHIC) {
        vec3 d = v / max(r, 1e-30);
        gl_Position = vec4(stereographic(d, n, t, b), clamp(r / pc.far, 0.0, 1.0), 1.0);
    } else {
        vec3 f, right, up;
        hemicube_axes(pc.face, n, t, b, f, right, up);
        float z = dot(v, f);
        float near = pc.far * 1e-6;
        gl_Position = vec4(dot(v, right), dot(v, up), (z - near) * pc.far / (pc.far - near), z);
    }
}
