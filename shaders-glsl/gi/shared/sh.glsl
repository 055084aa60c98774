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

// Three bands (9 coefficients, src/gi/shared/sh.rs `basis_l2`): the four above, then
// (Y2-2, Y2-1, Y20, Y21, Y22) with odd m's sign folded in.
const uint SH_L2_COEFFICIENTS = 9;

void sh_l2_basis(vec3 w, out float y[SH_L2_COEFFICIENTS]) {
    const float y0 = 0.28209479177387814;  // 1 / (2 sqrt(pi))
    const float y1 = 0.4886025119029199;   // sqrt(3 / (4 pi))
    const float cross_ = 1.0925484305920792; // sqrt(15 / (4 pi))
    const float zonal = 0.31539156525252005; // sqrt(5 / (16 pi))
    const float squares = 0.5462742152960396; // sqrt(15 / (16 pi))
    y[0] = y0;
    y[1] = -y1 * w.y;
    y[2] = y1 * w.z;
    y[3] = -y1 * w.x;
    y[4] = cross_ * w.x * w.y;
    y[5] = -cross_ * w.y * w.z;
    y[6] = zonal * (3.0 * w.z * w.z - 1.0);
    y[7] = -cross_ * w.x * w.z;
    y[8] = squares * (w.x * w.x - w.y * w.y);
}

// The clamped cosine's convolution factor of coefficient i's band: pi, 2pi/3, pi/4.
float sh_cosine_convolution(uint i) {
    return i == 0u ? 3.141592653589793 : (i < 4u ? 2.0943951023931953 : 0.7853981633974483);
}

#endif
