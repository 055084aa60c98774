#version 460
// ILPV clamp compensation, R, G and B in one dispatch, read as storage buffers.
#define CHANNELS 3
#define LPV_TEXELS 0
#include "gi/lpv/compensate.glsl"
