#version 460
// Binary voxelisation (spec 001 §4.6), conservative, in compute: one thread per triangle marks
// every voxel its surface touches, column by column along its dominant axis (the column's
// square overlaps the projected triangle; the voxels between the plane's lowest and highest
// depth over the square, within the triangle's depth range). Mirrors voxels.rs
// `voxelize_triangle`; every mark writes the same 1, so the order of threads does not matter.
#include "common/scene.glsl"

layout(local_size_x = 64) in;

layout(binding = RV_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = RV_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = RV_VOXEL_TARGET, std430) writeonly buffer Target { uint target[]; };

layout(push_constant) uniform Push {
    vec4 lo_voxel;      // the cube's minimum corner, a voxel's side
    uint resolution;
    uint triangle_count;
} pc;

void main() {
    // Triangles run along x and, past the dispatch limit of x, on along y.
    uint id = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (id >= pc.triangle_count) return;
    Triangle tri = triangles[id];
    vec3 v[3];
    for (uint i = 0u; i < 3u; ++i) v[i] = (vertices[tri[i]].position.xyz - pc.lo_voxel.xyz) / pc.lo_voxel.w;
    vec3 normal = cross(v[1] - v[0], v[2] - v[0]);
    vec3 a = abs(normal);
    if (max(a.x, max(a.y, a.z)) == 0.0) return;
    uint w = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
    uint u = (w + 1u) % 3u;
    uint vv = (w + 2u) % 3u;
    vec2 p[3];
    float depth[3];
    for (uint i = 0u; i < 3u; ++i) {
        p[i] = vec2(v[i][u], v[i][vv]);
        depth[i] = v[i][w];
    }
    float n = float(pc.resolution);
    vec2 lo = min(p[0], min(p[1], p[2]));
    vec2 hi = max(p[0], max(p[1], p[2]));
    if (hi.x < 0.0 || hi.y < 0.0 || lo.x >= n || lo.y >= n) return;
    uvec2 first = uvec2(max(floor(lo), vec2(0.0)));
    uvec2 last = uvec2(min(floor(hi), vec2(n - 1.0)));
    float orientation = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
    float sign_ = orientation >= 0.0 ? 1.0 : -1.0;
    vec3 edges[3];
    for (uint e = 0u; e < 3u; ++e) {
        vec2 s = p[e];
        vec2 t = p[(e + 1u) % 3u];
        vec2 en = vec2(-(t.y - s.y), t.x - s.x) * sign_;
        edges[e] = vec3(en, -(en.x * s.x + en.y * s.y));
    }
    float du = -normal[u] / normal[w];
    float dv = -normal[vv] / normal[w];
    float c = depth[0] - du * p[0].x - dv * p[0].y;
    float dmin = min(depth[0], min(depth[1], depth[2]));
    float dmax = max(depth[0], max(depth[1], depth[2]));
    float spread = 0.5 * (abs(du) + abs(dv));
    uint side = pc.resolution;
    for (uint j = first.y; j <= last.y; ++j) {
        for (uint i = first.x; i <= last.x; ++i) {
            vec2 xy = vec2(i, j);
            bool inside = true;
            for (uint e = 0u; e < 3u; ++e) {
                vec2 corner = xy + vec2(edges[e].x >= 0.0 ? 1.0 : 0.0, edges[e].y >= 0.0 ? 1.0 : 0.0);
                inside = inside && dot(edges[e].xy, corner) + edges[e].z >= 0.0;
            }
            if (!inside) continue;
            float centre = c + du * (xy.x + 0.5) + dv * (xy.y + 0.5);
            float z0 = max(centre - spread, dmin);
            float z1 = min(centre + spread, dmax);
            if (z1 < 0.0 || z0 >= n) continue;
            uint k0 = uint(max(floor(z0), 0.0));
            uint k1 = uint(min(floor(z1), n - 1.0));
            for (uint k = k0; k <= k1; ++k) {
                uvec3 voxel;
                voxel[u] = i;
                voxel[vv] = j;
                voxel[w] = k;
                target[voxel.x + side * (voxel.y + side * voxel.z)] = 1u;
            }
        }
    }
}
