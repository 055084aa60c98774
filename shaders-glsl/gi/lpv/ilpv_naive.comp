#version 460
// 26-neighbour ILPV step, sources read straight from global memory (for comparison).
#define LPV_COLUMN 0
#define LPV_TILED 0
#include "gi/lpv/ilpv_step.glsl"
