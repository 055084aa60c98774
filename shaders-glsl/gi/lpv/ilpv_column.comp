#version 460
// 26-neighbour ILPV step, a column of cells along z per thread, sources kept in registers.
#define LPV_TILED 0
#define LPV_COLUMN 1
#define COLUMN_FACES_ONLY 0
#include "gi/lpv/ilpv_step.glsl"
