#ifndef VKGI_RASTER_LIGHT_WORDS_GLSL
#define VKGI_RASTER_LIGHT_WORDS_GLSL
// Where the shared lights and their shadow views lie among the LIGHTING_VARYING_WORDS flat
// varyings of the fragment form of direct lighting (raster/lighting.vert writes them,
// raster/lighting.frag reads them): per light its 4 words, then SHARED_LIGHT_VIEWS views of 5
// words (the view-projection's columns and the parameters: all shadow_visibility reads).
// Requires raster/direct.glsl's specialisation constants.

const uint LIGHT_WORDS = LIGHTING_LIGHT_WORDS;
const uint VIEW_WORDS = LIGHTING_VIEW_WORDS;

// The first word of shared light `i`.
uint light_word(uint i) {
    return i * (LIGHT_WORDS + VIEW_WORDS * SHARED_LIGHT_VIEWS);
}

// The first word of view `f` of shared light `i`.
uint view_word(uint i, uint f) {
    return light_word(i) + LIGHT_WORDS + VIEW_WORDS * f;
}

#endif
