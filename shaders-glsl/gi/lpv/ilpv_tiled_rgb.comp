#version 460
// 26-neighbour ILPV step, R, G and B in one dispatch, sources from a shared-memory tile.
#define CHANNELS 3
#define LPV_TILED 1
#define LPV_COLUMN 0
#define LPV_TEXELS 0
#define COLUMN_FACES_ONLY 0
#include "gi/lpv/ilpv_step.glsl"
