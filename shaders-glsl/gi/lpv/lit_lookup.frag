#version 460
// Direct lighting and the lookup in one pass (lpv/lit_lookup_pass.glsl), the lattices as 3-D images
// the sampler filters (--lookup-filter sampler, lpv/lookup_light.glsl).
#include "gi/lpv/lit_lookup_pass.glsl"
