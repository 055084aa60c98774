#version 460
// The full-screen triangle of the fragment form of direct lighting (raster/lighting.frag), which
// reads the shared lights and their shadow views once per draw and hands them to every fragment
// as flat varyings (raster/lighting_vertex.glsl).
#include "raster/lighting_vertex.glsl"

void main() {
    cover_viewport();
    write_light_words();
}
