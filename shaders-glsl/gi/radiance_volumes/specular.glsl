#ifndef VKGI_RV_SPECULAR_GLSL
#define VKGI_RV_SPECULAR_GLSL
// Per-cache hemisphere maps of incoming light (spec 001 §4.7); src/gi/radiance_volumes/
// specular.rs is the f64 mirror and explains the quantities. A cache's map covers the half
// vectors around z = the direction to the cascades' eye, in the concentric square map of the
// Lambert equal-area disc (every texel subtends 2π/side² sr), side² vec4s per cache.
#include "common/math.glsl"
#include "common/sampling.glsl"

// Where unit h (h.z >= 0) falls in the unit square.
vec2 rv_hemisphere_map(vec3 h) {
    float r = 0.5 * sqrt(max(1.0 - min(h.z, 1.0), 0.0));
    if (r == 0.0) return vec2(0.5);  // atan(0, 0) is undefined in GLSL
    float phi = atan(h.y, h.x) * 4.0 / PI;
    if (phi < -1.0) phi += 8.0;
    vec2 square;
    if (phi < 1.0) square = vec2(r, phi * r);
    else if (phi < 3.0) square = vec2(-(phi - 2.0) * r, r);
    else if (phi < 5.0) square = vec2(-r, -(phi - 4.0) * r);
    else square = vec2((phi - 6.0) * r, -r);
    return square + 0.5;
}

// Direction d in the frame (t, b, z) around unit z.
vec3 rv_local(vec3 d, vec3 z) {
    vec3 t, b;
    orthonormal_basis(z, t, b);
    return vec3(dot(d, t), dot(d, b), dot(d, z));
}

// The direction [`rv_hemisphere_map`] sends to uv.
vec3 rv_hemisphere_unmap(vec2 uv) {
    vec2 ab = uv - 0.5;
    float r = max(abs(ab.x), abs(ab.y));
    if (r == 0.0) return vec3(0.0, 0.0, 1.0);
    float phi;
    if (abs(ab.x) >= abs(ab.y)) phi = ab.x > 0.0 ? ab.y / r : 4.0 - ab.y / r;
    else phi = ab.y > 0.0 ? 2.0 - ab.x / r : 6.0 + ab.x / r;
    phi *= PI / 4.0;
    float z = 1.0 - 4.0 * r * r;
    float s = sqrt(max(1.0 - z * z, 0.0));
    return vec3(s * cos(phi), s * sin(phi), z);
}

// The direction at the centre of texel k of a map of `side`.
vec3 rv_texel_centre(uint k, uint side) {
    return rv_hemisphere_unmap((vec2(k % side, k / side) + 0.5) / float(side));
}

// The texel holding the half vector of light from local direction l (0xFFFFFFFF for
// light from straight behind).
uint rv_specular_texel(vec3 l, uint side) {
    vec3 sum = l + vec3(0.0, 0.0, 1.0);
    if (dot(sum, sum) < 1e-12) return 0xFFFFFFFFu;
    vec2 uv = rv_hemisphere_map(normalize(sum));
    uvec2 texel = min(uvec2(uv * float(side)), uvec2(side - 1u));
    return texel.y * side + texel.x;
}

// A texel's angular size near the map's centre, in radians of half-vector angle.
float rv_texel_angle(uint side) {
    return 2.0 * sqrt(2.0) / float(side);
}

// The width D is evaluated with (specular.rs `sampled_alpha`): at least a quarter texel.
float rv_sampled_alpha(float alpha, uint side) {
    return max(alpha, rv_texel_angle(side) / 4.0);
}

// Points per texel side at which a lobe of alpha is evaluated near its axis (specular.rs
// `texel_samples`).
uint rv_texel_samples(float alpha, uint side) {
    return uint(clamp(ceil(2.0 * rv_texel_angle(side) / alpha), 1.0, 4.0));
}

// The cosine to the lobe's axis above which a texel is sampled finely (`near_cosine`).
float rv_near_cosine(float alpha, uint side) {
    return cos(min(rv_texel_angle(side) + 2.0 * alpha, PI));
}

#endif
