#ifndef VKGI_BVH_GLSL
#define VKGI_BVH_GLSL
// Ray casting through the scene BVH. The including shader declares the buffers `bvh_nodes` and
// `bvh_triangles` (BvhTriangle in leaf order) first.
#include "common/bvh_node.glsl"

// Möller–Trumbore on corner a and edges e1 = b - a, e2 = c - a; writes t and the barycentrics
// of corners b and c on a hit in (t_min, t_max).
bool intersect_triangle(vec3 origin, vec3 dir, vec3 a, vec3 e1, vec3 e2, float t_min, float t_max,
                        out float t, out vec2 uv) {
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-12) return false;
    float inv = 1.0 / det;
    vec3 s = origin - a;
    float u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(s, e1);
    float v = dot(dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(e2, q) * inv;
    uv = vec2(u, v);
    return t > t_min && t < t_max;
}

// Entry distance of the ray into a node's box, or -1 if it misses within (t_min, t_max).
float slab(BvhNode n, vec3 origin, vec3 inv_dir, float t_min, float t_max) {
    vec3 t0 = (n.min - origin) * inv_dir;
    vec3 t1 = (n.max - origin) * inv_dir;
    vec3 lo = min(t0, t1);
    vec3 hi = max(t0, t1);
    float near = max(max(max(lo.x, lo.y), lo.z), t_min);
    float far = min(min(min(hi.x, hi.y), hi.z), t_max);
    return near <= far ? near : -1.0;
}

// Closest hit (any_hit = false) or the first hit found (any_hit = true, for shadow rays),
// following the miss links (no stack). Returns the triangle index or -1; t and uv describe the hit.
int trace_ray(vec3 origin, vec3 dir, float t_min, float t_max, bool any_hit,
              out float t_hit, out vec2 uv_hit) {
    vec3 inv_dir = 1.0 / dir;
    int best = -1;
    float limit = t_max;
    t_hit = t_max;
    uv_hit = vec2(0.0);
    uint node = 0u;
    while (node != BVH_END) {
        BvhNode n = bvh_nodes[node];
        if (slab(n, origin, inv_dir, t_min, limit) < 0.0) {
            node = n.miss;
            continue;
        }
        if (n.leaf == 0u) {
            node += 1u;
            continue;
        }
        uint first = n.leaf >> BVH_LEAF_COUNT_BITS;
        uint end = first + (n.leaf & ((1u << BVH_LEAF_COUNT_BITS) - 1u));
        for (uint i = first; i < end; ++i) {
            BvhTriangle tri = bvh_triangles[i];
            float t;
            vec2 uv;
            if (intersect_triangle(origin, dir, tri.v0, tri.e1.xyz, tri.e2.xyz, t_min, limit, t, uv)) {
                limit = t;
                best = int(tri.index);
                t_hit = t;
                uv_hit = uv;
                if (any_hit) return best;
            }
        }
        node = n.miss;
    }
    return best;
}

#endif
