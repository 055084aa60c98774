#ifndef VKGI_RASTER_LIGHTING_PIXEL_GLSL
#define VKGI_RASTER_LIGHTING_PIXEL_GLSL
// The fragment side of direct lighting's fragment form (raster/direct.glsl's shading, the
// lights and their views from the flat varyings raster/lighting_vertex.glsl writes).
// raster/lighting.frag includes it, and so does a GI method's pass that draws direct light with
// its own (gi/lpv/lit_lookup.frag), which reads the G-buffer once for both.
#include "raster/direct.glsl"
#include "raster/light_words.glsl"

layout(location = 0) flat in vec4 words[LIGHTING_VARYING_WORDS];

// Shared light `i` as the vertex shader wrote it.
Light shared_light(uint i) {
    uint w = light_word(i);
    return Light(words[w], words[w + 1u], words[w + 2u], floatBitsToUint(words[w + 3u]));
}

// View `f` of shared light `i`: what shadow_visibility reads of it (the rest zero).
ShadowView shared_view(uint i, uint f) {
    uint v = view_word(i, f);
    mat4 view_projection = mat4(words[v], words[v + 1u], words[v + 2u], words[v + 3u]);
    return ShadowView(view_projection, words[v + 4u], vec4(0.0), vec4(0.0));
}

// The direct radiance (emission and direct light) `pixel` shows, and what it read of the
// G-buffer: its position (w 0: background) and its surface.
vec3 direct_radiance(ivec2 pixel, out vec4 position, out Surface s) {
    position = imageLoad(gbuffer_position, pixel);
    s = load_surface(pixel, position.xyz);
    vec3 irradiance = vec3(0.0);
    vec3 reflected = vec3(0.0);
    [[unroll]] for (uint i = 0u; i < SHARED_LIGHTS; ++i) {
        ShadowView views[SHARED_LIGHT_VIEWS];
        [[unroll]] for (uint f = 0u; f < SHARED_LIGHT_VIEWS; ++f) views[f] = shared_view(i, f);
        add_shared_light(i, shared_light(i), views, s, irradiance, reflected);
    }
    return shaded(s, position, irradiance, reflected);
}

#endif
