#version 460
// Deferred direct lighting: emission + the BRDF (albedo/pi and the glossy lobe of
// common/brdf.glsl) times each shadowed punctual light's irradiance, into the linear HDR target.
#include "common/math.glsl"
#include "common/lights.glsl"
#include "common/brdf.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = LIGHTING_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = LIGHTING_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;
layout(binding = LIGHTING_GBUFFER_ALBEDO, rgba16f) readonly uniform image2D gbuffer_albedo;
layout(binding = LIGHTING_GBUFFER_EMISSION, rgba16f) readonly uniform image2D gbuffer_emission;
layout(binding = LIGHTING_GBUFFER_SPECULAR, rgba16f) readonly uniform image2D gbuffer_specular;
layout(binding = LIGHTING_SHADOW_MAP) uniform sampler2DArray shadow_map;
layout(binding = LIGHTING_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = LIGHTING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView shadow_views[]; };
layout(binding = LIGHTING_HDR_OUT, rgba32f) writeonly uniform image2D hdr_out;

// What the scene's materials have (src/render/passes.rs): lavapipe runs both sides of every
// branch, so a term no material has is left out when the pipeline is built, not per pixel.
layout(constant_id = 0) const bool EMISSIVE = true;
layout(constant_id = 1) const bool GLOSSY = true;

layout(push_constant) uniform Push {
    vec4 camera_position;
    uvec2 size;
    uint light_count;
    uint include_direct;   // 0: indirect-only rendering, direct light and emission left out
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0 || pc.include_direct == 0u) {
        imageStore(hdr_out, pixel, vec4(0.0, 0.0, 0.0, 1.0));
        return;
    }
    vec3 p = position.xyz;
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 radiance = EMISSIVE ? imageLoad(gbuffer_emission, pixel).rgb : vec3(0.0);
    vec4 specular = GLOSSY ? imageLoad(gbuffer_specular, pixel) : vec4(0.0);
    bool glossy = GLOSSY && any(greaterThan(specular.rgb, vec3(0.0)));
    vec3 to_eye = normalize(pc.camera_position.xyz - p);
    vec3 irradiance = vec3(0.0);
    vec3 reflected = vec3(0.0);
    for (uint i = 0u; i < pc.light_count; ++i) {
        Light light = lights[i];
        vec3 to_light;
        float distance;
        vec3 e = light_incidence(light, p, to_light, distance);
        float cos_theta = dot(n, to_light);
        if (cos_theta <= 0.0 || all(equal(e, vec3(0.0)))) continue;
        uint view = shadow_view_index(light, p);
        float visibility = shadow_visibility(shadow_map, shadow_views[view], view, p, n, distance);
        irradiance += e * (cos_theta * visibility);
        if (glossy) reflected += e * visibility * glossy_cos(specular.rgb, specular.a, n, to_light, to_eye);
    }
    radiance += albedo * INV_PI * irradiance;
    if (glossy) radiance += reflected;
    imageStore(hdr_out, pixel, vec4(radiance, 1.0));
}
