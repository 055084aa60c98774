#ifndef VKGI_RV_SPECULAR_GLSL
#define VKGI_RV_SPECULAR_GLSL
// Per-cache hemisphere maps of incoming light (spec 001 §4.7); src/gi/radiance_volumes/
// specular.rs is the f64 mirror and explains the quantities. A cache's map covers the half
// vectors around z = the direction to the cascades' eye, in the concentric square map of the
// Lambert equal-area disc (every level-0 texel subtends 2π/side² sr); its levels follow one
// another in the cache's block of `rv_specular_texels(side)` vec4s.
#include "common/math.glsl"
#include "common/sampling.glsl"

// Where unit h (h.z >= 0) falls in the unit square.
vec2 rv_hemisphere_map(vec3 h) {
    float r = 0.5 * sqrt(max(1.0 - min(h.z, 1.0), 0.0));
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

uint rv_specular_levels(uint side) {
    return findLSB(side) + 1u;
}

// Where level `level` starts in a cache's texels.
uint rv_specular_level_offset(uint side, uint level) {
    uint offset = 0u;
    for (uint l = 0u; l < level; ++l) offset += (side >> l) * (side >> l);
    return offset;
}

// The level-0 texel holding the half vector of light from local direction l (RV_NONE for
// light from straight behind).
uint rv_specular_texel(vec3 l, uint side) {
    vec3 sum = l + vec3(0.0, 0.0, 1.0);
    if (dot(sum, sum) < 1e-12) return 0xFFFFFFFFu;
    vec2 uv = rv_hemisphere_map(normalize(sum));
    uvec2 texel = min(uvec2(uv * float(side)), uvec2(side - 1u));
    return texel.y * side + texel.x;
}

// The mip level whose bilinear footprint is about as wide as the GGX lobe (specular.rs `lod`).
float rv_specular_lod(uint side, float roughness) {
    float alpha = roughness * roughness;
    return clamp(log2(float(side) * alpha * 0.5), 0.0, float(rv_specular_levels(side) - 1u));
}

#endif
