#version 460
// Arithmetic-rate probe: independent vec4 FMA chains, unrolled so that the loop around them
// (the only branch) costs little against the FMAs it repeats; written out so the compiler keeps
// them. Each invocation does pc.iterations x LIMITS_FMA_UNROLL x CHAINS vec4 FMAs (8 flops
// each). How many chains hide the latency best depends on the CPU or GPU (src/app/limits.rs).
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = LIMITS_DESTINATION, std430) writeonly buffer Destination { vec4 destination[]; };

layout(constant_id = 0) const uint CHAINS = 2u;

layout(push_constant) uniform Push {
    uint count;
    uint iterations;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    vec4 chain[CHAINS];
    [[unroll]] for (int c = 0; c < int(CHAINS); ++c) {
        chain[c] = vec4(float(i) * 1e-7 + 0.25 * float(c), 0.1, 0.2, 0.3);
    }
    const vec4 m = vec4(0.9999, 0.9998, 0.9997, 0.9996);
    const vec4 k = vec4(1e-4, 2e-4, 3e-4, 4e-4);
    for (uint n = 0u; n < pc.iterations; ++n) {
        [[unroll]] for (int u = 0; u < int(LIMITS_FMA_UNROLL); ++u) {
            [[unroll]] for (int c = 0; c < int(CHAINS); ++c) chain[c] = fma(chain[c], m, k);
        }
    }
    vec4 sum = vec4(0.0);
    [[unroll]] for (int c = 0; c < int(CHAINS); ++c) sum += chain[c];
    if (i < pc.count) destination[i] = sum;
}
