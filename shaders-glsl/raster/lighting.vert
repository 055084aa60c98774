#version 460
// The full-screen triangle of the fragment form of direct lighting (raster/lighting.frag), which
// reads the shared lights and their shadow views once per draw and hands them to every fragment
// as flat varyings: a fragment shader reads buffers lane by lane on lavapipe
// (docs/performance.md).
#include "raster/direct.glsl"
#include "raster/light_words.glsl"

layout(binding = LIGHTING_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = LIGHTING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView shadow_views[]; };

layout(location = 0) flat out vec4 words[LIGHTING_VARYING_WORDS];

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
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
