#ifndef VKGI_LIGHTS_GLSL
#define VKGI_LIGHTS_GLSL
// Punctual lights (point, spot, and the cosine lobes that sample area lights) and their shadow
// maps. The Rust side is src/scene/gpu.rs (GpuLight,
// GpuShadowView) and src/scene/light.rs, whose spot profile this must match exactly.

struct Light {
    vec4 position_kind;        // xyz position, w = LIGHT_KIND_*
    vec4 direction_cos_outer;  // xyz axis, w = cos(outer cone angle)
    vec4 intensity_cos_inner;  // rgb peak intensity W/sr, w = cos(inner cone angle)
    uvec4 shadow;              // x = first shadow view, y = view count
};

struct ShadowView {
    mat4 view_projection;
    vec4 params;               // x = shadow texel size per unit distance, y near, z far,
                               // w = 2 tan(fov/2)
    vec4 axis_light;           // xyz view axis, w = light index
    vec4 origin;               // xyz the light's position, w = 1
};

float spot_profile(float cos_angle, float cos_outer, float cos_inner) {
    if (cos_angle <= cos_outer) return 0.0;
    if (cos_angle >= cos_inner) return 1.0;
    float t = (cos_angle - cos_outer) / max(cos_inner - cos_outer, 1e-9);
    return t * t;
}

// Unit direction from `p` toward the light, and the light's radiant intensity toward `p`
// divided by the squared distance (irradiance on a surface facing the light).
vec3 light_incidence(Light light, vec3 p, out vec3 to_light, out float distance) {
    vec3 d = light.position_kind.xyz - p;
    float dist_sq = max(dot(d, d), 1e-20);
    distance = sqrt(dist_sq);
    to_light = d / distance;
    float profile = 1.0;
    uint kind = uint(light.position_kind.w);
    if (kind == LIGHT_KIND_SPOT) {
        profile = spot_profile(dot(light.direction_cos_outer.xyz, -to_light),
                               light.direction_cos_outer.w, light.intensity_cos_inner.w);
    } else if (kind == LIGHT_KIND_COSINE) {
        profile = max(dot(light.direction_cos_outer.xyz, -to_light), 0.0);
    }
    return light.intensity_cos_inner.rgb * (profile / dist_sq);
}

// A spot light's frame across its axis (src/scene/gpu.rs light_frame is the same).
void light_frame(vec3 axis, out vec3 u, out vec3 v) {
    vec3 up = abs(axis.y) > 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(0.0, 1.0, 0.0);
    u = normalize(cross(up, axis));
    v = cross(axis, u);
}

// Which of a light's shadow views covers `p`, counted from its first: cube face by major axis
// for point lights (6 views), the front or a side face of the cube around the axis for wide
// spots and cosine lobes (5 views), 0 for a light with one view.
uint shadow_face(Light light, vec3 p) {
    if (light.shadow.y <= 1u) return 0u;
    vec3 d = p - light.position_kind.xyz;
    uint face;
    if (light.shadow.y == 5u) {
        vec3 axis = light.direction_cos_outer.xyz;
        vec3 u, v;
        light_frame(axis, u, v);
        vec3 l = vec3(dot(d, axis), dot(d, u), dot(d, v));
        if (l.x >= abs(l.y) && l.x >= abs(l.z)) face = 0u;
        else if (abs(l.y) >= abs(l.z)) face = l.y >= 0.0 ? 1u : 2u;
        else face = l.z >= 0.0 ? 3u : 4u;
        return face;
    }
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) face = d.x >= 0.0 ? 0u : 1u;
    else if (a.y >= a.z) face = d.y >= 0.0 ? 2u : 3u;
    else face = d.z >= 0.0 ? 4u : 5u;
    return face;
}

// The index of the shadow view (and shadow-map layer) that covers `p`.
uint shadow_view_index(Light light, vec3 p) {
    return light.shadow.x + shadow_face(light, p);
}

// The depths of the 2x2 texels from `base` in layer `layer` of a map of `size` texels, in one
// gather at the corner their centres share, as (i0 j1, i1 j1, i1 j0, i0 j0). The map must be
// bound with a clamp-to-edge sampler without depth comparison (the frame's shadow sampler):
// texels past the map's edges read its edge.
vec4 gather_texels(sampler2DArray map, ivec2 base, ivec2 size, uint layer) {
    return textureGather(map, vec3(vec2(base + 1) / vec2(size), float(layer)), 0);
}

// Fraction of the light reaching `p` (normal `n`), from a 3x3 bilinear PCF of the shadow map
// (a 4x4-texel tent). The lookup point is pushed along the normal by 1.5 shadow texels.
// `shadow_map` must be bound with a clamp-to-edge sampler without depth comparison (the frame's
// shadow sampler): its gathers return the stored depths, clamped at the map's edges.
float shadow_visibility(sampler2DArray shadow_map, ShadowView view, uint layer, vec3 p, vec3 n,
                        float distance) {
    vec3 offset_p = p + n * (1.5 * view.params.x * distance);
    vec4 clip = view.view_projection * vec4(offset_p, 1.0);
    if (clip.w <= 0.0) return 1.0;
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0) return 1.0;
    ivec2 size = textureSize(shadow_map, 0).xy;
    vec2 t = uv * vec2(size) - 0.5;
    ivec2 base = ivec2(floor(t));
    vec2 f = t - vec2(base);
    float wx[4] = float[4](1.0 - f.x, 1.0, 1.0, f.x);
    float wy[4] = float[4](1.0 - f.y, 1.0, 1.0, f.y);
    // The 4x4 texels around `base` as four 2x2 gathers: occluder[j][i] is texel
    // base + (i - 1, j - 1).
    float occluder[4][4];
    for (int gj = 0; gj < 2; ++gj) {
        for (int gi = 0; gi < 2; ++gi) {
            vec4 g = gather_texels(shadow_map, base + ivec2(2 * gi - 1, 2 * gj - 1), size, layer);
            occluder[2 * gj + 1][2 * gi] = g.x;
            occluder[2 * gj + 1][2 * gi + 1] = g.y;
            occluder[2 * gj][2 * gi + 1] = g.z;
            occluder[2 * gj][2 * gi] = g.w;
        }
    }
    float lit = 0.0;
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            lit += wx[i] * wy[j] * (ndc.z <= occluder[j][i] ? 1.0 : 0.0);
        }
    }
    return lit / 9.0;
}

#endif
