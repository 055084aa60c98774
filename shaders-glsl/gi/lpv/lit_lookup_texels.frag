#version 460
// Direct lighting and the lookup in one pass (lpv/lit_lookup_pass.glsl), the lattices read as
// texels and interpolated in the shader (--lookup-filter texels, lpv/lookup_light.glsl).
#define LOOKUP_TEXELS 1
#include "gi/lpv/lit_lookup_pass.glsl"
