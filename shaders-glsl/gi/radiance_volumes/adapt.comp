#version 460
// Temporal occupancy adaptation (spec 001 §4.6): each voxel of level 0 moves toward the binary
// target by at most `step` a frame (1: at once), so geometry that moved fades in and out.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(binding = RV_VOXEL_TARGET, std430) readonly buffer Target { uint target[]; };
layout(binding = RV_VOXELS, std430) buffer Voxels { float voxels[]; };

layout(push_constant) uniform Push {
    uint side;          // voxels per side of level 0
    float step;
} pc;

void main() {
    uvec3 v = gl_GlobalInvocationID;
    if (any(greaterThanEqual(v, uvec3(pc.side)))) return;
    uint i = v.x + pc.side * (v.y + pc.side * v.z);
    float goal = float(target[i]);
    float now = voxels[i];
    voxels[i] = now + clamp(goal - now, -pc.step, pc.step);
}
