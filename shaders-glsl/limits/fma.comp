#version 460
// Arithmetic-rate probe: four independent vec4 FMA chains per invocation (8 flops per component
// FMA counted as 2), written out so the compiler keeps them.
layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = LIMITS_DESTINATION, std430) writeonly buffer Destination { vec4 destination[]; };

layout(push_constant) uniform Push {
    uint count;
    uint iterations;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 a = vec4(float(i) * 1e-7, 0.1, 0.2, 0.3);
    vec4 b = a + 0.25;
    vec4 c = a + 0.5;
    vec4 d = a + 0.75;
    const vec4 m = vec4(0.9999, 0.9998, 0.9997, 0.9996);
    const vec4 k = vec4(1e-4, 2e-4, 3e-4, 4e-4);
    for (uint n = 0u; n < pc.iterations; ++n) {
        a = fma(a, m, k);
        b = fma(b, m, k);
        c = fma(c, m, k);
        d = fma(d, m, k);
    }
    destination[i] = a + b + c + d;
}
