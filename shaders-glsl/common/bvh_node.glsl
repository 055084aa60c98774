#ifndef VKGI_BVH_NODE_GLSL
#define VKGI_BVH_NODE_GLSL
// BVH nodes and leaf triangles as src/scene/bvh.rs lays them out (std430).

struct BvhNode {
    vec3 min;
    uint miss;    // next node when the box is missed or the subtree is done; BVH_END ends
    vec3 max;
    uint leaf;    // 0 for interior nodes (first child = this + 1); first << 5 | count for leaves
};

const uint BVH_END = 0xFFFFFFFFu;
const uint BVH_LEAF_COUNT_BITS = 5u;

// A triangle in leaf order, ready for Möller–Trumbore: a corner, two edges, and the index of
// the triangle in the scene.
struct BvhTriangle {
    vec3 v0;
    uint index;
    vec4 e1;
    vec4 e2;
};

#endif
