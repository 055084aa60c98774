#ifndef VKGI_RASTER_LIGHTING_VERTEX_GLSL
#define VKGI_RASTER_LIGHTING_VERTEX_GLSL
// The vertex side of direct lighting's fragment form: the full-screen triangle, and the shared
// lights and their shadow views read once per draw and handed to every fragment as the
// LIGHTING_VARYING_WORDS flat varyings at locations 0 on (raster/light_words.glsl's layout): a
// fragment shader reads buffers lane by lane on lavapipe (docs/performance.md).
// raster/lighting.vert includes it, and so does a GI method's pass that draws direct light with
// its own (gi/lpv/lit_lookup.vert); raster/lighting_pixel.glsl is the fragment side.
#include "raster/direct.glsl"
#include "raster/light_words.glsl"

layout(binding = LIGHTING_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = LIGHTING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView shadow_views[]; };

layout(location = 0) flat out vec4 words[LIGHTING_VARYING_WORDS];

// Vertex gl_VertexIndex of the triangle that covers the viewport (clip space -1..3), at the far
// plane (common/fullscreen.vert says why).
void cover_viewport() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
}

// The shared lights and their views into `words`.
void write_light_words() {
    [[unroll]] for (uint i = 0u; i < SHARED_LIGHTS; ++i) {
        Light light = lights[i];
        uint w = light_word(i);
        words[w] = light.position_kind;
        words[w + 1u] = light.direction_cos_outer;
        words[w + 2u] = light.intensity_cos_inner;
        words[w + 3u] = uintBitsToFloat(light.shadow);
        uint first = shared_first_view(i);
        uint last = shared_last_view(i);
        [[unroll]] for (uint f = 0u; f < SHARED_LIGHT_VIEWS; ++f) {
            ShadowView view = shadow_views[first + min(f, last)];
            uint v = view_word(i, f);
            [[unroll]] for (int c = 0; c < 4; ++c) words[v + uint(c)] = view.view_projection[c];
            words[v + 4u] = view.params;
        }
    }
}

#endif
