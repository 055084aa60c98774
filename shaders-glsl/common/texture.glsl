#ifndef VKGI_TEXTURE_GLSL
#define VKGI_TEXTURE_GLSL
// Albedo textures, the rule of src/scene/texture.rs: 8-bit sRGB texels decoded to linear,
// bilinear between texel centres, repeating, no mipmaps. The includer declares
//     readonly buffer Textures { uint texture_words[]; };
// laid out by src/scene/gpu.rs: per texture a uvec4 (first texel word, width, height, 0), then
// the texels, r | g << 8 | b << 16 | a << 24, row-major from the top row.
#include "common/scene.glsl"

// False when no material of the scene has a texture (src/shader_shared.rs).
layout(constant_id = SPEC_SCENE_TEXTURED) const bool SCENE_TEXTURED = true;

float srgb_to_linear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

vec3 texture_texel(uint first, ivec2 size, ivec2 at) {
    ivec2 wrapped = ((at % size) + size) % size;
    uint t = texture_words[first + uint(wrapped.y * size.x + wrapped.x)];
    vec3 c = vec3(float(t & 0xffu), float((t >> 8) & 0xffu), float((t >> 16) & 0xffu)) / 255.0;
    return vec3(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
}

vec3 sample_albedo_texture(uint index, vec2 uv) {
    uint first = texture_words[4u * index];
    ivec2 size = ivec2(texture_words[4u * index + 1u], texture_words[4u * index + 2u]);
    vec2 p = (uv - floor(uv)) * vec2(size) - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    ivec2 i = ivec2(p0);
    vec3 top = mix(texture_texel(first, size, i), texture_texel(first, size, i + ivec2(1, 0)), f.x);
    vec3 bottom = mix(texture_texel(first, size, i + ivec2(0, 1)),
                      texture_texel(first, size, i + ivec2(1, 1)), f.x);
    return mix(top, bottom, f.y);
}

// The material's albedo at texture coordinates `uv`: the factor, times the texture if it has one.
vec3 material_albedo(Material m, vec2 uv) {
    uint texture_plus_one = uint(m.albedo.w);
    if (!SCENE_TEXTURED || texture_plus_one == 0u) return m.albedo.rgb;
    return m.albedo.rgb * sample_albedo_texture(texture_plus_one - 1u, uv);
}

#endif
