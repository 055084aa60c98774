#ifndef VKGI_LPV_LOOKUP_SURFACE_GLSL
#define VKGI_LPV_LOOKUP_SURFACE_GLSL
// The G-buffer as the lookup's own passes read it (src/gi/lpv/lookup.rs binds it): a pixel's
// surface position (w 0: background), unit normal and albedo. Direct lighting's pass reads it
// in raster/direct.glsl instead when the lookup is drawn inside that pass. A pass that needs no
// albedo (the half-resolution lookup, which looks up light per unit albedo) defines
// LOOKUP_READS_ALBEDO 0 and is bound no albedo image.
#ifndef LOOKUP_READS_ALBEDO
#define LOOKUP_READS_ALBEDO 1
#endif

layout(binding = LOOKUP_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LOOKUP_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
#if LOOKUP_READS_ALBEDO
layout(binding = LOOKUP_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
#endif

// The surface position at `pixel`; w is 0 where no surface covers it.
vec4 surface_position(ivec2 pixel) {
    return imageLoad(gbuffer_position, pixel);
}

// The unit normal at `pixel`.
vec3 surface_normal(ivec2 pixel) {
    return normalize(imageLoad(gbuffer_normal, pixel).xyz);
}

#if LOOKUP_READS_ALBEDO
// The albedo at `pixel`.
vec3 surface_albedo(ivec2 pixel) {
    return imageLoad(gbuffer_albedo, pixel).rgb;
}
#endif

#endif
