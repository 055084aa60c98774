#version 460
// The lookup as a pass of its own (lpv/lookup_pass.glsl), the lattices read as texels
// and interpolated in the shader (--lookup-filter texels, lpv/lookup_light.glsl).
#define LOOKUP_TEXELS 1
#include "gi/lpv/lookup_pass.glsl"
