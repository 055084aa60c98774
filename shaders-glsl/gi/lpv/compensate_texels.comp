#version 460
// ILPV clamp compensation, one colour channel a dispatch, read as texels.
#define CHANNELS 1
#define LPV_TEXELS 1
#include "gi/lpv/compensate.glsl"
