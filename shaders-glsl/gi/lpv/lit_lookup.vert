#version 460
// The full-screen triangle of direct lighting with the lookup (lpv/lit_lookup.frag): the shared
// lights and their views (raster/lighting_vertex.glsl), then the lookup's fields
// (lpv/lookup_fields.glsl), as flat varyings.
#define LOOKUP_FIELDS_LOCATION LIGHTING_VARYING_WORDS
#include "raster/lighting_vertex.glsl"
#include "gi/lpv/lookup_fields.glsl"

void main() {
    cover_viewport();
    write_light_words();
    write_field_words();
}
