#version 460
#extension GL_EXT_control_flow_attributes : require
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

// lavapipe reads a buffer once for all the pixels of a SIMD batch only at an index made of
// constants and push constants, outside every branch; at any other index (a loop counter, a
// light's first view) it reads lane by lane, which cost this pass a quarter of its time. So a
// scene with at most MAX_SHARED_LIGHTS lights (src/render/passes.rs) is shaded by an unrolled
// loop at constant indices: SHARED_LIGHTS is its light count (0: any count, read in a loop up
// to pc.light_count), and SHARED_LIGHT_VIEWS the most shadow views one of them has.
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

// What one pixel needs to shade: its surface and the direction to the eye.
struct Surface {
    vec3 p;
    vec3 n;
    vec4 specular;
    bool glossy;
    vec3 to_eye;
};

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

// Shared light `i` (a constant): its data and its shadow views read at indices every pixel
// shares, the view covering the pixel selected among them.
void add_shared_light(uint i, Surface s, inout vec3 irradiance, inout vec3 reflected) {
    Light light = lights[i];
    uint first = pc.first_view[i / 4u][i % 4u];
    uint last = pc.view_count[i / 4u][i % 4u] - 1u;
    ShadowView views[SHARED_LIGHT_VIEWS];
    [[unroll]] for (uint f = 0u; f < SHARED_LIGHT_VIEWS; ++f) views[f] = shadow_views[first + min(f, last)];
    uint face = shadow_face(light, s.p);
    ShadowView view = views[0];
    [[unroll]] for (uint f = 1u; f < SHARED_LIGHT_VIEWS; ++f) {
        if (face == f) view = views[f];
    }
    add_light(light, view, first + face, s, irradiance, reflected);
}

// Emission plus the reflected light of every shadowed punctual light at a covered pixel.
vec3 direct_radiance(ivec2 pixel, vec3 p) {
    Surface s;
    s.p = p;
    s.n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 radiance = EMISSIVE ? imageLoad(gbuffer_emission, pixel).rgb : vec3(0.0);
    s.specular = GLOSSY ? imageLoad(gbuffer_specular, pixel) : vec4(0.0);
    s.glossy = GLOSSY && any(greaterThan(s.specular.rgb, vec3(0.0)));
    s.to_eye = normalize(pc.camera_position.xyz - p);
    vec3 irradiance = vec3(0.0);
    vec3 reflected = vec3(0.0);
    if (SHARED_LIGHTS > 0u) {
        [[unroll]] for (uint i = 0u; i < SHARED_LIGHTS; ++i) add_shared_light(i, s, irradiance, reflected);
    } else {
        for (uint i = 0u; i < pc.light_count; ++i) {
            Light light = lights[i];
            uint view = shadow_view_index(light, p);
            add_light(light, shadow_views[view], view, s, irradiance, reflected);
        }
    }
    radiance += albedo * INV_PI * irradiance;
    if (s.glossy) radiance += reflected;
    return radiance;
}

void main() {
    // No early return: lavapipe would put everything after it in a branch. Invocations past
    // the image's edge shade its last row or column and store nothing.
    uvec2 id = gl_GlobalInvocationID.xy;
    ivec2 pixel = ivec2(min(id, pc.size - 1u));
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 radiance = direct_radiance(pixel, position.xyz);
    bool lit = position.w != 0.0 && pc.include_direct != 0u;
    if (all(lessThan(id, pc.size))) imageStore(hdr_out, pixel, vec4(lit ? radiance : vec3(0.0), 1.0));
}
