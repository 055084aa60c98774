#version 460
// 26-neighbour ILPV step, sources from a shared-memory tile.
#define LPV_COLUMN 0
#define LPV_TILED 1
#include "gi/lpv/ilpv_step.glsl"
