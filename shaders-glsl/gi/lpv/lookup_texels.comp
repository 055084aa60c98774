#version 460
// The lookup as a compute pass (lpv/lookup_compute.glsl), the lattices read as texels and
// interpolated in the shader (--lookup-filter texels, lpv/lookup_light.glsl).
#define LOOKUP_TEXELS 1
#include "gi/lpv/lookup_compute.glsl"
