#version 460
// Classic 6-neighbour LPV step, one colour channel, a column of cells along z per thread, sources
// kept in registers and read as texels.
#define CHANNELS 1
#define LPV_TILED 0
#define LPV_COLUMN 1
#define LPV_TEXELS 1
#define COLUMN_FACES_ONLY 1
#define COLUMN_STREAM 0
#include "gi/lpv/kd10_step.glsl"
