#version 460
// A record's hemisphere texel: the radiance the visible surface reflects toward the record (its
// direct light from the shadow maps, plus from the second bounce on the indirect irradiance the
// previous bounce's snapshot gathers there, times albedo / pi; emission is direct light, which
// the frame draws itself) and the distance to it.
#include "common/scene.glsl"
#include "common/lights.glsl"
#include "gi/irradiance_cache/ic.glsl"

layout(binding = IC_TEXTURES, std430) readonly buffer Textures { uint texture_words[]; };
#include "common/texture.glsl"

layout(binding = IC_MATERIALS, std430) readonly buffer Materials { Material materials[]; };
layout(binding = IC_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = IC_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView shadow_views[]; };
layout(binding = IC_SHADOW_MAP) uniform sampler2DArray shadow_map;
layout(binding = IC_PREVIOUS, std430) readonly buffer Previous { Record previous[]; };
layout(binding = IC_STATE, std430) readonly buffer State { CacheState state; };

layout(push_constant) uniform Push {
    uint slot;
    float near;
    float far;
    float half_width;
    uint light_count;
    float accuracy;       // the snapshot's weighting (bounces past the first)
    float smooth_weight;
    float normal_factor;
} pc;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) flat in vec3 in_face_normal;
layout(location = 3) flat in uint in_material;
layout(location = 4) in vec2 in_texcoord;
layout(location = 5) flat in vec3 in_eye;

layout(location = 0) out vec4 out_radiance_distance;

// The previous bounce's indirect irradiance at p, n: every snapshot record's weighted,
// extrapolated irradiance, normalised (the splat's sums, gathered); none where no record reaches.
vec3 snapshot_irradiance(vec3 p, vec3 n) {
    Weighting weighting = Weighting(pc.accuracy, pc.smooth_weight, pc.normal_factor);
    vec4 sums = vec4(0.0);
    for (uint k = 0u; k < state.previous_count; ++k) {
        float w = record_weight(previous[k], weighting, p, n);
        if (w > 0.0) sums += vec4(w * record_extrapolate(previous[k], p, n), w);
    }
    return sums.w > 0.0 ? sums.rgb / sums.w : vec3(0.0);
}

void main() {
    float facing = dot(in_face_normal, in_eye - in_position) >= 0.0 ? 1.0 : -1.0;
    vec3 n = shading_normal(in_normal, in_face_normal) * facing;
    if (dot(n, in_face_normal * facing) <= 0.0) n = in_face_normal * facing;
    vec3 albedo = material_albedo(materials[in_material], in_texcoord);
    vec3 irradiance = vec3(0.0);
    for (uint i = 0u; i < pc.light_count; ++i) {
        Light light = lights[i];
        vec3 to_light;
        float distance_to_light;
        vec3 e = light_incidence(light, in_position, to_light, distance_to_light);
        float cos_theta = dot(n, to_light);
        if (cos_theta <= 0.0 || all(equal(e, vec3(0.0)))) continue;
        uint view = shadow_view_index(light, in_position);
        irradiance += e * (cos_theta * shadow_visibility(shadow_map, shadow_views[view], view,
                                                         in_position, n, distance_to_light));
    }
    if (state.bounce > 1u) irradiance += snapshot_irradiance(in_position, n);
    out_radiance_distance = vec4(albedo * INV_PI * irradiance, distance(in_position, in_eye));
}
