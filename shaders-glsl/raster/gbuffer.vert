#version 460
// G-buffer geometry: every material parameter and the eye go to the fragment stage.
#define GBUFFER_EYE
#define MATERIAL_TERMS
#include "common/raster_vertex.glsl"
