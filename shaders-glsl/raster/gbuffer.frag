#version 460
// The G-buffer of a scene whose materials emit or have a glossy lobe: all five targets.
#define MATERIAL_TERMS
#include "raster/gbuffer.glsl"
