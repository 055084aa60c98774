#version 460
// The lookup as a compute pass (lpv/lookup_compute.glsl), the lattices as 3-D images the
// sampler filters (--lookup-filter sampler, lpv/lookup_light.glsl).
#include "gi/lpv/lookup_compute.glsl"
