#version 460
// One level of the occupancy mip chain (spec 001 §4.6): each voxel the mean of its 8 children,
// the fraction of the finer volume that is full (voxels.rs `mips`).
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(binding = RV_VOXELS, std430) buffer Voxels { float voxels[]; };

layout(push_constant) uniform Push {
    uint source;        // first voxel of the level below
    uint target;        // first voxel of this level
    uint side;          // voxels per side of this level
} pc;

void main() {
    uvec3 v = gl_GlobalInvocationID;
    if (any(greaterThanEqual(v, uvec3(pc.side)))) return;
    uint below = 2u * pc.side;
    float sum = 0.0;
    for (uint k = 0u; k < 8u; ++k) {
        uvec3 c = 2u * v + uvec3(k & 1u, (k >> 1) & 1u, k >> 2);
        sum += voxels[pc.source + c.x + below * (c.y + below * c.z)];
    }
    voxels[pc.target + v.x + pc.side * (v.y + pc.side * v.z)] = sum * 0.125;
}
