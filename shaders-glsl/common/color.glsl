#ifndef VKGI_COLOR_GLSL
#define VKGI_COLOR_GLSL

// Reinhard's L / (1 + L) per channel (seed 000's view-independent operator).
vec3 tonemap_reinhard(vec3 radiance) {
    return radiance / (1.0 + radiance);
}

#endif
