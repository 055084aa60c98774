#ifndef VKGI_LPV_HALF_LIGHT_GLSL
#define VKGI_LPV_HALF_LIGHT_GLSL
// A texel of the half-resolution lookup (--lookup-resolution half; lpv/lookup_half.frag writes
// it, lpv/upsample.glsl reads it): the light the lattices send toward the surface seen at the
// full-resolution pixel (2x, 2y), per unit albedo, and what the upsample weighs it by: that
// surface's distance from the eye and its normal. x, y: R, G and B as half floats, scaled by
// 2^-e for the exponent e of the brightest (the high half of y holds e + 128): eleven bits of
// each, over a float's range; z: the distance as a float (UPSAMPLE_NO_SURFACE for
// background); w: the normal, octahedral, two snorm16. src/gi/lpv/upsample.rs mirrors the
// upsample in f64.

// The octahedral map of unit vector `n` onto [-1, 1]².
vec2 octahedral(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 e = n.xy;
    if (n.z < 0.0) {
        vec2 signs = vec2(e.x >= 0.0 ? 1.0 : -1.0, e.y >= 0.0 ? 1.0 : -1.0);
        e = (1.0 - abs(e.yx)) * signs;
    }
    return e;
}

// The unit vector whose octahedral map is `e`.
vec3 from_octahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float fold = max(-n.z, 0.0);
    n.x += n.x >= 0.0 ? -fold : fold;
    n.y += n.y >= 0.0 ? -fold : fold;
    return normalize(n);
}

uvec4 pack_half_light(vec3 light, float distance_to_eye, vec3 n) {
    int e;
    frexp(max(max(light.r, light.g), max(light.b, 1e-30)), e);
    e = clamp(e, -126, 127);
    vec3 scaled = ldexp(light, ivec3(-e));
    uint b_and_exponent = (packHalf2x16(vec2(scaled.b, 0.0)) & 0xffffu) | (uint(e + 128) << 16);
    return uvec4(packHalf2x16(scaled.rg), b_and_exponent, floatBitsToUint(distance_to_eye),
                 packSnorm2x16(octahedral(n)));
}

void unpack_half_light(uvec4 texel, out vec3 light, out float distance_to_eye, out vec3 n) {
    int e = int(texel.y >> 16) - 128;
    light = ldexp(vec3(unpackHalf2x16(texel.x), unpackHalf2x16(texel.y).x), ivec3(e));
    distance_to_eye = uintBitsToFloat(texel.z);
    n = from_octahedral(unpackSnorm2x16(texel.w));
}

#endif
