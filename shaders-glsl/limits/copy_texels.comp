#version 460
// Memory-bandwidth probe, the texel variant: copy.comp with its source read as texels (a
// vectorised gather on lavapipe, where a storage-buffer load is a loop over the lanes; 1.35x
// the storage-buffer copy there). The limit is the faster of the two, so that no pass beats it
// whichever way it reads.
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
