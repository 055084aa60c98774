#version 460
// Memory-bandwidth probe: copy vec4s from one buffer to another (16 bytes read + 16 written
// per invocation), the access pattern of a propagation step's streaming part.
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = LIMITS_SOURCE, std430) readonly buffer Source { vec4 source[]; };
layout(binding = LIMITS_DESTINATION, std430) writeonly buffer Destination { vec4 destination[]; };

layout(push_constant) uniform Push {
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < pc.count) destination[i] = source[i];
}
