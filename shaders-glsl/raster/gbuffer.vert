#version 460
// G-buffer geometry: every material parameter goes to the fragment stage.
#include "common/raster_vertex.glsl"
