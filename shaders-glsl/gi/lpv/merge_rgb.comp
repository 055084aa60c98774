#version 460
// The ILPV blend of R, G and B in one dispatch.
#define CHANNELS 3
#include "gi/lpv/merge.glsl"
