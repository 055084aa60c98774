#ifndef VKGI_LPV_UPSAMPLE_GLSL
#define VKGI_LPV_UPSAMPLE_GLSL
// The upsample of the half-resolution lookup (--lookup-resolution half): a full-resolution
// pixel's light per unit albedo from the four half-resolution texels around it, each weighted
// bilinearly and by how alike its surface is to the pixel's: its distance from the eye, times
// the cosine between the pixel's normal and its ray (at least UPSAMPLE_MIN_FACING), within
// UPSAMPLE_DISTANCE_TOLERANCE of the pixel's distance (a tent: about the texel's distance from
// the pixel's plane, so a surface seen at a grazing angle, whose distance changes fast from
// pixel to pixel, keeps its neighbours), and its normal (cos^8, three squarings). Texel (i, j)
// holds full-resolution pixel (2i, 2j), so a pixel at even coordinates reads its own surface's
// light. Where the weights sum to UPSAMPLE_LEAST_WEIGHT or less, the most alike texel's light
// (the first of those within UPSAMPLE_MISS_MARGIN): at a silhouette, a pixel whose four texels
// all lie on other surfaces or on background takes theirs, so geometry thinner than two pixels
// may get another surface's light or none. src/gi/lpv/upsample.rs mirrors it in f64, with the
// same constants (src/gi/lpv/bindings.rs).
#extension GL_EXT_control_flow_attributes : require
#include "gi/lpv/half_light.glsl"

layout(binding = LOOKUP_HALF_LIGHT, rgba32ui) readonly uniform uimage2D half_light;


vec3 upsampled_light(ivec2 pixel, vec3 position, vec3 n, vec3 eye) {
    float d = distance(position, eye);
    float facing = max(abs(dot(n, eye - position)) / d, UPSAMPLE_MIN_FACING);
    ivec2 last = imageSize(half_light) - 1;
    ivec2 base = pixel >> 1;
    vec2 f = vec2(pixel & 1) * 0.5;
    vec3 sum = vec3(0.0);
    float total = 0.0;
    vec3 nearest = vec3(0.0);
    float nearest_miss = 3.0e38;
    [[unroll]] for (int k = 0; k < 4; ++k) {
        ivec2 corner = ivec2(k & 1, k >> 1);
        vec3 light;
        float d_texel;
        vec3 n_texel;
        unpack_half_light(imageLoad(half_light, min(base + corner, last)), light, d_texel, n_texel);
        vec2 bilinear = mix(1.0 - f, f, vec2(corner));
        float gap = abs(d_texel - d) * facing / (UPSAMPLE_DISTANCE_TOLERANCE * d);
        float cosine = max(dot(n_texel, n), 0.0);
        float alike = cosine * cosine;
        alike *= alike;
        alike *= alike;
        float w = bilinear.x * bilinear.y * max(1.0 - gap, 0.0) * alike;
        // A texel of no weight adds nothing (0 times a light of inf would add NaN).
        if (w > 0.0) {
            sum += w * light;
            total += w;
        }
        float miss = gap + 1.0 - cosine;
        if (miss + UPSAMPLE_MISS_MARGIN < nearest_miss) {
            nearest_miss = miss;
            nearest = light;
        }
    }
    return total > UPSAMPLE_LEAST_WEIGHT ? sum / total : nearest;
}

#endif
