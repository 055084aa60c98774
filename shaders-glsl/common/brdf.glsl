#ifndef VKGI_BRDF_GLSL
#define VKGI_BRDF_GLSL
// The shared surface model (src/scene/brdf.rs is the same arithmetic): albedo / pi plus a GGX
// lobe specular * D(h) G(l, v) / (4 (n.l)(n.v)), alpha = roughness^2, separable Smith G, no
// Fresnel factor.
#include "common/math.glsl"

float ggx_d(float n_h, float a2) {
    float d = n_h * n_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

float smith_g1(float n_x, float a2) {
    return 2.0 * n_x / (n_x + sqrt(a2 + (1.0 - a2) * n_x * n_x));
}

// The glossy lobe times n.l for light from l seen from v.
vec3 glossy_cos(vec3 specular, float roughness, vec3 n, vec3 l, vec3 v) {
    float n_l = dot(n, l);
    float n_v = dot(n, v);
    if (n_l <= 0.0 || n_v <= 0.0) return vec3(0.0);
    float a = roughness * roughness;
    float a2 = a * a;
    vec3 h = normalize(l + v);
    float n_h = max(dot(n, h), 0.0);
    return specular * (ggx_d(n_h, a2) * smith_g1(n_l, a2) * smith_g1(n_v, a2) / (4.0 * n_v));
}

// Density (solid angle) of sample_glossy choosing l.
float glossy_pdf(float roughness, vec3 n, vec3 l, vec3 v) {
    vec3 h = normalize(l + v);
    float n_h = dot(n, h);
    float v_h = dot(v, h);
    if (n_h <= 0.0 || v_h <= 0.0) return 0.0;
    float a = roughness * roughness;
    float a2 = a * a;
    return ggx_d(n_h, a2) * n_h / (4.0 * v_h);
}

// v reflected about a GGX normal drawn by D(h)(n.h) in the tangent frame (t, b, n).
vec3 sample_glossy(float roughness, vec3 t, vec3 b, vec3 n, vec3 v, float u1, float u2) {
    float a = roughness * roughness;
    float a2 = a * a;
    float cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    float cos_h = sqrt(max(cos2, 0.0));
    float sin_h = sqrt(max(1.0 - cos2, 0.0));
    float phi = 2.0 * PI * u2;
    vec3 h = normalize(t * (sin_h * cos(phi)) + b * (sin_h * sin(phi)) + n * cos_h);
    return normalize(h * (2.0 * dot(v, h)) - v);
}

// The glossy lobe's share of bounces (0 for Lambertian surfaces).
float glossy_share(vec3 albedo, vec3 specular) {
    float s = specular.x + specular.y + specular.z;
    float d = albedo.x + albedo.y + albedo.z;
    return s > 0.0 ? s / (s + d) : 0.0;
}

#endif
