#version 460
// Classic 6-neighbour LPV step, sources from a shared-memory tile.
#define LPV_COLUMN 0
#define LPV_TILED 1
#include "gi/lpv/kd10_step.glsl"
