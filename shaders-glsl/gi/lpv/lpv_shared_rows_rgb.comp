#version 460
// Classic 6-neighbour LPV step, R, G and B in one dispatch, a column of cells along z per thread, each row's cells shared
// across the subgroup's lanes (gi/lpv/tile.glsl, COLUMN_SHARED_ROWS).
#define CHANNELS 3
#define LPV_TILED 0
#define LPV_COLUMN 1
#define LPV_TEXELS 1
#define COLUMN_FACES_ONLY 1
#define COLUMN_STREAM 0
#define COLUMN_SHARED_ROWS 1
#include "gi/lpv/kd10_step.glsl"
