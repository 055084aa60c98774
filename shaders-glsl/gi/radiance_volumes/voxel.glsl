#ifndef VKGI_RV_VOXEL_GLSL
#define VKGI_RV_VOXEL_GLSL
// The occupancy mip chain and the cone march through it (spec 001 §4.6), mirroring
// src/gi/radiance_volumes/voxels.rs `sample` and `cone_visibility`. The includer declares
// `float voxels[]` (every level, level 0 first).

struct VoxelGrid {
    vec3 lo;            // the cube's minimum corner
    float voxel;        // a voxel's side
    uint resolution;    // voxels per side of level 0 (a power of two)
    uint levels;
};

const float CONE_START = 2.0;

// First voxel of `level`: sum over l < level of (n >> l)^3 = (n^3 - m^3) / 7 * 8, m = n >> level.
uint voxel_offset(VoxelGrid g, uint level) {
    uint n = g.resolution;
    uint m = n >> level;
    return (n * n * n - m * m * m) / 7u * 8u;
}

float voxel_sample_level(VoxelGrid g, vec3 p, uint level) {
    int side = int(g.resolution >> level);
    vec3 q = p / float(1u << level) - 0.5;
    vec3 base = floor(q);
    vec3 f = q - base;
    uint offset = voxel_offset(g, level);
    float sum = 0.0;
    for (uint k = 0u; k < 8u; ++k) {
        ivec3 c = ivec3(k & 1u, (k >> 1) & 1u, k >> 2);
        ivec3 v = ivec3(base) + c;
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(side)))) continue;
        vec3 axis = mix(1.0 - f, f, vec3(c));
        sum += axis.x * axis.y * axis.z * voxels[offset + uint(v.x + side * (v.y + side * v.z))];
    }
    return sum;
}

// Occupancy at p (level-0 voxel units) filtered at `lod`: trilinear in a level, linear between.
float voxel_sample(VoxelGrid g, vec3 p, float lod) {
    lod = clamp(lod, 0.0, float(g.levels - 1u));
    uint level = uint(floor(lod));
    float fine = voxel_sample_level(g, p, level);
    if (lod == float(level)) return fine;
    return mix(fine, voxel_sample_level(g, p, level + 1u), lod - float(level));
}

// Visibility from `from` to `to` (world) through a cone of aperture s (radius per unit length),
// at most `steps` samples (voxels.rs CONE_STEPS says why 16), from CONE_START voxels out until
// a sample's footprint (its radius, at least a voxel) would come within a voxel of `to`, or of
// the target's own surface: the plane through `to` with unit normal `normal`, within `extent`
// (world) of `to` along it. That surface does not hide its own light, however grazing the
// cone's approach.
float cone_visibility(VoxelGrid g, vec3 from, vec3 to, vec3 normal, float s, float extent,
                      uint steps) {
    vec3 x = (from - g.lo) / g.voxel;
    vec3 y = (to - g.lo) / g.voxel;
    float distance = length(y - x);
    if (distance == 0.0) return 1.0;
    vec3 direction = (y - x) / distance;
    float half_extent = 0.5 * extent / g.voxel;
    float t = CONE_START;
    float occlusion = 0.0;
    for (uint i = 0u; i < steps; ++i) {
        float r = t * s;
        vec3 p = x + direction * t;
        float clearance = max(r, 1.0) + 1.0;
        float height = dot(p - y, normal);
        bool over_target = length((p - y) - height * normal) < clearance + half_extent;
        if (t + clearance >= distance || (over_target && height <= clearance)) break;
        float alpha = voxel_sample(g, p, log2(max(r, 1e-30)));
        occlusion += (1.0 - occlusion) * alpha;
        t += max(2.0 * r / (1.0 - s), 1.0);
    }
    return clamp(1.0 - occlusion, 0.0, 1.0);
}

#endif
