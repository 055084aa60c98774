#version 460
// Direct lighting and the lookup in one pass (lpv/lit_lookup_pass.glsl), the lattices read as
// texels and interpolated in the shader, the fetches shared across the subgroup
// (--lookup-filter shared-texels, lpv/lookup_light.glsl).
#define LOOKUP_TEXELS 1
#define LOOKUP_SHARED_CORNERS 1
#include "gi/lpv/lit_lookup_pass.glsl"
