// LightWave's shading, shared by both gathers (spec 002 §2.4-2.5): the thesis's gather (eq 4.5
// without its specular part: vkgi's surfaces are Lambertian), the indirect visibility from the
// VPL shadow maps (accurate: the mean of K maps; integrated: taps interpolated between the pairs
// of 5 maps), and the composite, added to the HDR image that already holds the frame's
// shadowed direct light. The including shader defines `prepare_gather` and `gathered`. src/gi/lightwave/cpu.rs is
// the f64 gather.
#include "common/math.glsl"
#include "common/lights.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = GATHER_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = GATHER_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = GATHER_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = GATHER_VPLS) uniform samplerBuffer vpls;
layout(binding = GATHER_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = GATHER_SCENE_SHADOW_MAP) uniform sampler2DArray scene_shadow_map;
layout(binding = GATHER_SCENE_SHADOW_VIEWS, std430) readonly buffer SceneShadowViews {
    ShadowView scene_shadow_views[];
};
layout(binding = GATHER_VPL_SHADOW_MAP) uniform sampler2DArray vpl_shadow_map;
struct VplShadowView {
    mat4 view_projection;
    vec4 eye_texel;   // xyz the VPL's position, w = texel size per unit distance
};
// Each map's view as five texels (the view-projection's columns, then eye_texel): lavapipe
// reads a storage buffer at any index but constants and push constants (here a loop counter)
// lane by lane, in a loop with a branch a lane, where a texel fetch is one gather.
layout(binding = GATHER_VPL_SHADOW_VIEWS) uniform samplerBuffer vpl_views;

VplShadowView vpl_view(uint layer) {
    int first = 5 * int(layer);
    mat4 view_projection = mat4(texelFetch(vpl_views, first), texelFetch(vpl_views, first + 1),
                                texelFetch(vpl_views, first + 2), texelFetch(vpl_views, first + 3));
    return VplShadowView(view_projection, texelFetch(vpl_views, first + 4));
}
layout(binding = GATHER_HDR, rgba32f) uniform image2D hdr;

layout(push_constant) uniform Push {
    uvec2 size;
    float fake;             // the fake-indirect multiplier m (eq 5.2)
    float gain;             // G (1/m²): indirect irradiance = G * I * gather
} pc;

// What the settings fix, set when the pipeline is built (src/gi/lightwave/mod.rs
// `gather_specialization`): lavapipe runs both sides of every branch for every pixel, and a
// loop's body at least once, so with these as push constants every pixel ran the integrated
// shadows' loops in accurate mode and the shipped composite's direct light in every mode.
layout(constant_id = 0) const uint LIGHT_COUNT = 1u;
layout(constant_id = 1) const uint PER_LIGHT = 1u;      // VPLs per light
layout(constant_id = 2) const uint SHADOW_MODE = 0u;    // SHADOWS_*
layout(constant_id = 3) const uint MAPS_PER_LIGHT = 0u; // VPL shadow maps per light
layout(constant_id = 4) const uint STEPS = 1u;          // integrated: interpolation steps per pair
layout(constant_id = 5) const uint COMPOSITE = 0u;      // COMPOSITE_*

#include "gi/lightwave/rig_gather.glsl"

// The thesis's gather for light l.
float gather(uint l, vec3 p, vec3 n) {
    return rig_gather(l * PER_LIGHT, PER_LIGHT, p, n);
}

// One shadow-map tap at homogeneous clip position `clip` of VPL shadow map `layer`: a 2x2
// bilinear comparison (the thesis's LINEAR depth compare); 1 outside the map.
float tap(uint layer, vec4 clip) {
    if (clip.w <= 0.0) return 1.0;
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0) {
        return 1.0;
    }
    ivec2 size = textureSize(vpl_shadow_map, 0).xy;
    vec2 t = uv * vec2(size) - 0.5;
    ivec2 base = ivec2(floor(t));
    vec2 f = t - vec2(base);
    vec4 lit = vec4(lessThanEqual(vec4(ndc.z), gather_texels(vpl_shadow_map, base, size, layer)));
    return mix(mix(lit.w, lit.z, f.x), mix(lit.x, lit.y, f.x), f.y);
}

// The clip position of p (moved 1.5 texels along n against acne) in VPL shadow map `layer`.
vec4 shadow_clip(uint layer, vec3 p, vec3 n) {
    VplShadowView view = vpl_view(layer);
    float offset = 1.5 * view.eye_texel.w * distance(view.eye_texel.xyz, p);
    return view.view_projection * vec4(p + n * offset, 1.0);
}

// Fraction of light l's shadow-casting VPLs that see p: accurate, the mean of its maps;
// integrated, per pair (a, b) of its 5 maps steps+1 taps at t = k/steps between the two clip
// positions, read in map a for t < 1/2, map b for t > 1/2, both at t = 1/2 (so one step gives
// the 5 maps' mean).
float visibility(uint l, vec3 p, vec3 n) {
    uint first = l * MAPS_PER_LIGHT;
    if (SHADOW_MODE == SHADOWS_ACCURATE) {
        float sum = 0.0;
        for (uint i = 0u; i < MAPS_PER_LIGHT; ++i) {
            sum += tap(first + i, shadow_clip(first + i, p, n));
        }
        return sum / float(MAPS_PER_LIGHT);
    }
    if (SHADOW_MODE == SHADOWS_INTEGRATED) {
        float sum = 0.0;
        for (uint a = 0u; a < 5u; ++a) {
            vec4 clip_a = shadow_clip(first + a, p, n);
            for (uint b = a + 1u; b < 5u; ++b) {
                vec4 clip_b = shadow_clip(first + b, p, n);
                for (uint k = 0u; k <= STEPS; ++k) {
                    vec4 clip = mix(clip_a, clip_b, float(k) / float(STEPS));
                    if (2u * k < STEPS) sum += tap(first + a, clip);
                    else if (2u * k > STEPS) sum += tap(first + b, clip);
                    else sum += 0.5 * (tap(first + a, clip) + tap(first + b, clip));
                }
            }
        }
        return sum / (10.0 * float(STEPS + 1u));
    }
    return 1.0;
}

// The frame's direct irradiance at p, shadowed (as raster/lighting.comp) and unshadowed.
void direct_irradiance(vec3 p, vec3 n, out vec3 shadowed, out vec3 unshadowed) {
    shadowed = vec3(0.0);
    unshadowed = vec3(0.0);
    for (uint i = 0u; i < LIGHT_COUNT; ++i) {
        Light light = lights[i];
        vec3 to_light;
        float distance;
        vec3 e = light_incidence(light, p, to_light, distance);
        float cos_theta = dot(n, to_light);
        if (cos_theta <= 0.0 || all(equal(e, vec3(0.0)))) continue;
        uint view = shadow_view_index(light, p);
        float visible = shadow_visibility(scene_shadow_map, scene_shadow_views[view], view, p, n, distance);
        unshadowed += e * cos_theta;
        shadowed += e * (cos_theta * visible);
    }
}

// What the gather needs at this pixel, whatever the light (once per pixel).
void prepare_gather(ivec2 pixel, vec3 p, vec3 n);
// The gather of light l at this pixel: gather.comp evaluates it here, gather_vertex.comp
// interpolates it from the triangle's corners.
float gathered(uint l, vec3 p, vec3 n);

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0 || COMPOSITE == COMPOSITE_DIRECT_ONLY) return;
    vec3 p = position.xyz;
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo_over_pi = imageLoad(gbuffer_albedo, pixel).rgb * INV_PI;
    vec3 added = vec3(0.0);
    if (COMPOSITE == COMPOSITE_EQ_4_9 || COMPOSITE == COMPOSITE_SHIPPED) {
        vec3 irradiance = vec3(0.0);
        prepare_gather(pixel, p, n);
        for (uint l = 0u; l < LIGHT_COUNT; ++l) {
            float s = gathered(l, p, n);
            if (s == 0.0) continue;
            float v = visibility(l, p, n);
            // As shipped, accurate shadows: 0.2 unshadowed + 0.8 shadowed, the visibility
            // divided by half the map count (the code's /10 with 20 maps, range 0..2).
            if (COMPOSITE == COMPOSITE_SHIPPED && SHADOW_MODE == SHADOWS_ACCURATE) {
                v = 0.2 + 0.8 * 2.0 * v;
            }
            irradiance += lights[l].intensity_cos_inner.rgb * (pc.gain * s * v);
        }
        added = albedo_over_pi * irradiance;
    }
    if (COMPOSITE == COMPOSITE_SHIPPED || COMPOSITE == COMPOSITE_FAKE) {
        // As shipped: 0.5 direct shadowed + 0.5 direct unshadowed; fake (eq 5.2):
        // 0.5 shadowed + (m - 0.5) unshadowed. The frame already added the shadowed direct.
        vec3 shadowed, unshadowed;
        direct_irradiance(p, n, shadowed, unshadowed);
        float m = COMPOSITE == COMPOSITE_FAKE ? pc.fake : 1.0;
        added += albedo_over_pi * ((m - 0.5) * unshadowed - 0.5 * shadowed);
    }
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(added, 0.0));
}
