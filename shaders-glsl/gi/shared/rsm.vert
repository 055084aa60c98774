#version 460
// Reflective shadow map geometry: the G-buffer's vertex stage, passing only the albedo of the
// material (the flux a surface reflects).
#include "common/raster_vertex.glsl"
