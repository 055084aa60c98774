#ifndef VKGI_SH_GLSL
#define VKGI_SH_GLSL
// Two-band SH in seed 000's convention (src/gi/lpv/sh.rs): (Y00, Y1-1, Y10, Y11) with the
// Condon–Shortley sign folded in; the clamped-cosine lobe around n is (c0, -c1 ny, c1 nz, -c1 nx).

const float SH_C0 = 0.886226925452758;       // sqrt(pi) / 2
const float SH_C1 = 1.0233267079464885;      // sqrt(pi / 3)
const float SH_SQRT_PI_2 = 3.544907701811032; // 2 sqrt(pi): <f|1> = 2 sqrt(pi) f.x

vec4 sh_cosine_lobe(vec3 n) {
    return vec4(SH_C0, -SH_C1 * n.y, SH_C1 * n.z, -SH_C1 * n.x);
}

#endif
