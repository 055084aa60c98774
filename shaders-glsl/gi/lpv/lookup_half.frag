#version 460
// The lookup at half resolution (lpv/lookup_half_pass.glsl), the lattices as 3-D images
// the sampler filters (--lookup-filter sampler, lpv/lookup_light.glsl).
#include "gi/lpv/lookup_half_pass.glsl"
