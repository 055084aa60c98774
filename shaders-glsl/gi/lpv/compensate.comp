#version 460
// ILPV clamp compensation, one colour channel a dispatch, read as a storage buffer.
#define CHANNELS 1
#define LPV_TEXELS 0
#include "gi/lpv/compensate.glsl"
