#version 460
// G-buffer geometry for a scene without emission or glossy lobes (raster/gbuffer_plain.frag):
// the albedo and the eye go to the fragment stage.
#define GBUFFER_EYE
#include "common/raster_vertex.glsl"
