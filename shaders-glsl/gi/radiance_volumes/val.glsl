#ifndef VKGI_RV_VAL_GLSL
#define VKGI_RV_VAL_GLSL
// A virtual area light: a block of RSM texels seen as one emitter (src/gi/radiance_volumes/cpu.rs
// `Val`, which the VAL passes mirror).
struct Val {
    vec4 position_texels;  // xyz mean position of the covered texels, w their count
    vec4 normal_area;      // xyz sum of their unit normals, w their area across the light's rays
    vec4 flux_depth;       // rgb reflected flux, w mean distance to the light
    vec4 depth_squared;    // x mean squared distance to the light
};
#endif
