#version 460
// The G-buffer of a scene whose materials neither emit nor have a glossy lobe: position, normal
// and albedo.
#include "raster/gbuffer.glsl"
