#ifndef VKGI_COLOR_GLSL
#define VKGI_COLOR_GLSL

// Linear -> sRGB transfer function (IEC 61966-2-1), per channel, input clamped to [0, 1].
vec3 srgb_encode(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 low = 12.92 * c;
    vec3 high = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(low, high, step(vec3(0.0031308), c));
}

// Reinhard's L / (1 + L) per channel (seed 000's view-independent operator).
vec3 tonemap_reinhard(vec3 radiance) {
    return radiance / (1.0 + radiance);
}

#endif
