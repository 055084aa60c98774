#version 460
// 26-neighbour ILPV step, R, G and B in one dispatch, a column of cells along z per thread, sources
// kept in registers and read as texels.
#define CHANNELS 3
#define LPV_TILED 0
#define LPV_COLUMN 1
#define LPV_TEXELS 1
#define COLUMN_FACES_ONLY 0
#define COLUMN_STREAM 1
#include "gi/lpv/ilpv_step.glsl"
