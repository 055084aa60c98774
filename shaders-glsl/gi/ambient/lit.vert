#version 460
// The full-screen triangle of direct lighting with the ambient term (ambient/lit.frag): the
// shared lights and their views (raster/lighting_vertex.glsl), then the irradiance E as one
// more flat varying, read once per draw.
#include "raster/lighting_vertex.glsl"

layout(binding = AMBIENT_IRRADIANCE, std430) readonly buffer Irradiance {
    vec4 irradiance_words;  // rgb: E per channel (W/m²)
};

layout(location = LIGHTING_VARYING_WORDS) flat out vec4 irradiance;

void main() {
    cover_viewport();
    write_light_words();
    irradiance = irradiance_words;
}
