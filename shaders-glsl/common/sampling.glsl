#ifndef VKGI_SAMPLING_GLSL
#define VKGI_SAMPLING_GLSL
#include "common/math.glsl"

// An orthonormal basis around unit n (Duff et al. 2017), as (tangent, bitangent).
void orthonormal_basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction around unit n from two uniform numbers (pdf = cos / pi).
vec3 sample_cosine_hemisphere(vec3 n, float u1, float u2) {
    float r = sqrt(u1);
    float phi = 2.0 * PI * u2;
    vec3 t, b;
    orthonormal_basis(n, t, b);
    return normalize(t * (r * cos(phi)) + b * (r * sin(phi)) + n * sqrt(max(0.0, 1.0 - u1)));
}

#endif
