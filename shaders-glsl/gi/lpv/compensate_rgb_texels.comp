#version 460
// ILPV clamp compensation, R, G and B in one dispatch, read as texels.
#define CHANNELS 3
#define LPV_TEXELS 1
#include "gi/lpv/compensate.glsl"
