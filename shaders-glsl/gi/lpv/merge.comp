#version 460
// The ILPV blend of one colour channel.
#define CHANNELS 1
#include "gi/lpv/merge.glsl"
