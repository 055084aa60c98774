#version 460
// Classic 6-neighbour LPV step, sources read straight from global memory (for comparison).
#define LPV_COLUMN 0
#define LPV_TILED 0
#include "gi/lpv/kd10_step.glsl"
