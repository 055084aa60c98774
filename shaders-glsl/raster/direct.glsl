#ifndef VKGI_RASTER_DIRECT_GLSL
#define VKGI_RASTER_DIRECT_GLSL
// Deferred direct lighting's shading, shared by its two forms: emission + the BRDF (albedo/pi
// and the glossy lobe of common/brdf.glsl) times each shadowed punctual light's irradiance.
// raster/lighting.comp (a compute pass over the view, any number of lights) and
// raster/lighting.frag (a fragment pass whose lights arrive as flat varyings,
// raster/lighting.vert) include it and say where the lights come from.
#extension GL_EXT_control_flow_attributes : require
#include "common/math.glsl"
#include "common/lights.glsl"
#include "common/brdf.glsl"

layout(binding = LIGHTING_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LIGHTING_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LIGHTING_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = LIGHTING_GBUFFER_EMISSION, rgba16f) readonly uniform image2D gbuffer_emission;
layout(binding = LIGHTING_GBUFFER_SPECULAR, rgba16f) readonly uniform image2D gbuffer_specular;
layout(binding = LIGHTING_SHADOW_MAP) uniform sampler2DArray shadow_map;

// What the scene's materials have (src/render/passes.rs): lavapipe runs both sides of every
// branch, so a term no material has is left out when the pipeline is built, not per pixel.
layout(constant_id = 0) const bool EMISSIVE = true;
layout(constant_id = 1) const bool GLOSSY = true;

// lavapipe reads a buffer once for all the pixels of a SIMD batch only at an index made of
// constants and push constants, outside every branch; at any other index (a loop counter, a
// light's first view) it reads lane by lane, which cost this pass a quarter of its time. So a
// scene with at most MAX_SHARED_LIGHTS lights (src/render/passes.rs) is shaded by an unrolled
// loop at constant indices: SHARED_LIGHTS is its light count (0: any count, read in a loop up
// to pc.light_count; the compute form only), and SHARED_LIGHT_VIEWS the most shadow views one
// of them has.
layout(constant_id = 2) const uint SHARED_LIGHTS = 0u;
layout(constant_id = 3) const uint SHARED_LIGHT_VIEWS = 1u;

layout(push_constant) uniform Push {
    vec4 camera_position;
    uvec2 size;
    uint light_count;
    uint include_direct;   // 0: indirect-only rendering, direct light and emission left out
    uvec4 first_view[2];   // with SHARED_LIGHTS: each light's first shadow view (8 lights,
    uvec4 view_count[2];   // MAX_SHARED_LIGHTS) and its number of views
} pc;

// Shared light `i`'s first shadow view and its last view counted from the first.
uint shared_first_view(uint i) {
    return pc.first_view[i / 4u][i % 4u];
}

uint shared_last_view(uint i) {
    return pc.view_count[i / 4u][i % 4u] - 1u;
}

// What one pixel needs to shade: its surface and the direction to the eye.
struct Surface {
    vec3 p;
    vec3 n;
    vec3 albedo;
    vec3 emission;
    vec4 specular;
    bool glossy;
    vec3 to_eye;
};

// The G-buffer's surface at `pixel`, whose position is `p`.
Surface load_surface(ivec2 pixel, vec3 p) {
    Surface s;
    s.p = p;
    s.n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    s.albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    s.emission = EMISSIVE ? imageLoad(gbuffer_emission, pixel).rgb : vec3(0.0);
    s.specular = GLOSSY ? imageLoad(gbuffer_specular, pixel) : vec4(0.0);
    s.glossy = GLOSSY && any(greaterThan(s.specular.rgb, vec3(0.0)));
    s.to_eye = normalize(pc.camera_position.xyz - p);
    return s;
}

// Adds `light`'s irradiance and glossy reflection at `s`, seen through shadow `view` (layer
// `layer` of the shadow map).
void add_light(Light light, ShadowView view, uint layer, Surface s, inout vec3 irradiance,
               inout vec3 reflected) {
    vec3 to_light;
    float distance;
    vec3 e = light_incidence(light, s.p, to_light, distance);
    float cos_theta = dot(s.n, to_light);
    if (cos_theta > 0.0 && any(notEqual(e, vec3(0.0)))) {
        float visibility = shadow_visibility(shadow_map, view, layer, s.p, s.n, distance);
        irradiance += e * (cos_theta * visibility);
        if (s.glossy) reflected += e * visibility * glossy_cos(s.specular.rgb, s.specular.a, s.n, to_light, s.to_eye);
    }
}

// Shared light `light` (number `i`, a constant) with its views `views`: the view covering the
// pixel selected among them.
void add_shared_light(uint i, Light light, ShadowView views[SHARED_LIGHT_VIEWS], Surface s,
                      inout vec3 irradiance, inout vec3 reflected) {
    uint face = shadow_face(light, s.p);
    ShadowView view = views[0];
    [[unroll]] for (uint f = 1u; f < SHARED_LIGHT_VIEWS; ++f) {
        if (face == f) view = views[f];
    }
    add_light(light, view, shared_first_view(i) + face, s, irradiance, reflected);
}

// The radiance a pixel shows: emission plus the reflected light (`irradiance`, `reflected`)
// at a covered pixel (`position.w` != 0) when direct light is rendered, black otherwise.
vec3 shaded(Surface s, vec4 position, vec3 irradiance, vec3 reflected) {
    vec3 radiance = s.emission;
    radiance += s.albedo * INV_PI * irradiance;
    if (s.glossy) radiance += reflected;
    bool lit = position.w != 0.0 && pc.include_direct != 0u;
    return lit ? radiance : vec3(0.0);
}

#endif
