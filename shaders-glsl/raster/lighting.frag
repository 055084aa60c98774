#version 460
// Deferred direct lighting as a fragment pass over a full-screen triangle
// (raster/direct.glsl), for scenes whose SHARED_LIGHTS lights and their views fit the flat
// varyings raster/lighting.vert fills (src/render/passes.rs chooses). Against the compute form
// it trades the imageStore of the HDR pixel for a render target's write and reads the lights
// from varyings, the same for every fragment: the same radiance, in less time on lavapipe
// (docs/performance.md).
#include "raster/direct.glsl"
#include "raster/light_words.glsl"

layout(location = 0) flat in vec4 words[LIGHTING_VARYING_WORDS];
layout(location = 0) out vec4 out_radiance;

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

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = imageLoad(gbuffer_position, pixel);
    Surface s = load_surface(pixel, position.xyz);
    vec3 irradiance = vec3(0.0);
    vec3 reflected = vec3(0.0);
    [[unroll]] for (uint i = 0u; i < SHARED_LIGHTS; ++i) {
        ShadowView views[SHARED_LIGHT_VIEWS];
        [[unroll]] for (uint f = 0u; f < SHARED_LIGHT_VIEWS; ++f) views[f] = shared_view(i, f);
        add_shared_light(i, shared_light(i), views, s, irradiance, reflected);
    }
    out_radiance = vec4(shaded(s, position, irradiance, reflected), 1.0);
}
