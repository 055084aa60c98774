#version 460
// The lookup as a pass of its own (lpv/lookup_pass.glsl), the lattices as 3-D images
// the sampler filters (--lookup-filter sampler, lpv/lookup_light.glsl).
#include "gi/lpv/lookup_pass.glsl"
