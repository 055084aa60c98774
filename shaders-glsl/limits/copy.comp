#version 460
// Memory-bandwidth probe: copy vec4s from one buffer to another (16 bytes read + 16 written
// per invocation), the access pattern of a propagation step's streaming part. The source is read
// as texels, the fastest read found on lavapipe (a vectorised gather; 1.35x a storage-buffer
// copy there), so that no pass that reads that way can beat the bound.
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = LIMITS_SOURCE) uniform samplerBuffer source;
layout(binding = LIMITS_DESTINATION, std430) writeonly buffer Destination { vec4 destination[]; };

layout(push_constant) uniform Push {
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < pc.count) destination[i] = texelFetch(source, int(i));
}
