#ifndef VKGI_COLOR_GLSL
#define VKGI_COLOR_GLSL

// Reinhard's L / (1 + L) per channel (seed 000's view-independent operator).
vec3 tonemap_reinhard(vec3 radiance) {
    return radiance / (1.0 + radiance);
}

// The sRGB transfer function (IEC 61966-2-1) of linear values in [0, 1]: what an sRGB
// attachment applies to a fragment's output, for a pass that stores to a UNORM image instead.
vec3 srgb_encode(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 curve = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(curve, 12.92 * c, lessThanEqual(c, vec3(0.0031308)));
}

#endif
