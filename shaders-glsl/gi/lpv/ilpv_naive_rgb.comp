#version 460
// 26-neighbour ILPV step, R, G and B in one dispatch, sources read straight from global memory (for
// comparison).
#define CHANNELS 3
#define LPV_TILED 0
#define LPV_COLUMN 0
#define LPV_TEXELS 0
#define COLUMN_FACES_ONLY 0
#include "gi/lpv/ilpv_step.glsl"
