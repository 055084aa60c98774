#version 460
// The reference path tracer: Lambertian surfaces with an optional GGX lobe (common/brdf.glsl);
// punctual lights by next-event estimation;
// emissive triangles both by next-event estimation (a triangle chosen by power, a point on it
// uniformly; src/reference/emitters.rs) and by bounces that hit them (cosine-weighted, or by the
// GGX normals with the glossy lobe's share of the reflectance), the two
// combined by multiple importance sampling with the power heuristic. Emission leaves the front
// face (by winding) only unless the material is two-sided. One invocation per pixel adds
// `samples` samples to the direct and indirect sums. src/reference/cpu.rs is the same
// estimator on the CPU.
//
// Light transport kept: with a bounce limit B, paths reflect at most B + 1 times (B = 0: direct
// light only; B = 1: direct and one indirect bounce); unlimited paths end by Russian roulette
// after `rr_start` bounces. "Direct" = emission seen by the camera, and light reflected once.
#include "common/math.glsl"
#include "common/scene.glsl"
#include "common/lights.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/brdf.glsl"
#include "common/bvh_node.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = REFERENCE_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(binding = REFERENCE_TRIANGLES, std430) readonly buffer Triangles { Triangle triangles[]; };
layout(binding = REFERENCE_MATERIALS, std430) readonly buffer Materials { Material materials[]; };
layout(binding = REFERENCE_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = REFERENCE_BVH_NODES, std430) readonly buffer BvhNodes { BvhNode bvh_nodes[]; };
layout(binding = REFERENCE_BVH_TRIANGLES, std430) readonly buffer BvhTriangles { BvhTriangle bvh_triangles[]; };
layout(binding = REFERENCE_DIRECT_SUM, std430) buffer DirectSum { vec4 direct_sum[]; };
layout(binding = REFERENCE_INDIRECT_SUM, std430) buffer IndirectSum { vec4 indirect_sum[]; };
// Emissive triangles: x = mesh triangle, y = cumulative probability (float bits).
layout(binding = REFERENCE_EMITTERS, std430) readonly buffer Emitters { uvec2 emitters[]; };
layout(binding = REFERENCE_TEXTURES, std430) readonly buffer Textures { uint texture_words[]; };
#include "common/texture.glsl"

#include "common/bvh.glsl"

layout(push_constant) uniform Push {
    mat4 inverse_view_projection;
    vec4 camera_position_epsilon;  // xyz camera, w = ray offset (scene scale)
    uvec2 size;
    uint first_sample;
    uint samples;
    uint seed;
    uint max_bounces;              // REFERENCE_UNLIMITED_BOUNCES for no limit
    uint light_count;
    uint rr_start;
    uint has_emission;             // 0: no emissive surface, so the last bounce can find nothing
    uint emitter_count;
    float emitter_power;           // total emitted power (mean over RGB)
    uint strategy;                 // REFERENCE_STRATEGY_*
} pc;

// Density per unit area of next-event estimation picking a point of a material's emitter.
float emitter_area_pdf(Material m) {
    float sides = m.emission.w > 0.5 ? 2.0 : 1.0;
    return pc.emitter_power > 0.0
        ? PI * sides * (m.emission.r + m.emission.g + m.emission.b) / 3.0 / pc.emitter_power
        : 0.0;
}

// Power heuristic weight of a strategy of density `a` against one of density `b`.
float power_heuristic(float a, float b) {
    float a2 = a * a;
    return a2 / max(a2 + b * b, 1e-30);
}

vec3 camera_ray(vec2 pixel) {
    vec2 ndc = pixel / vec2(pc.size) * 2.0 - 1.0;
    vec4 near = pc.inverse_view_projection * vec4(ndc, 0.0, 1.0);
    vec4 far = pc.inverse_view_projection * vec4(ndc, 1.0, 1.0);
    return normalize(far.xyz / far.w - near.xyz / near.w);
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, pc.size))) return;
    uint pixel_index = pixel.y * pc.size.x + pixel.x;
    float eps = pc.camera_position_epsilon.w;
    bool unlimited = pc.max_bounces == REFERENCE_UNLIMITED_BOUNCES;
    vec3 direct = vec3(0.0);
    vec3 indirect = vec3(0.0);
    for (uint s = 0u; s < pc.samples; ++s) {
        uint sample_index = pc.first_sample + s;
        vec2 jitter = vec2(random_float(pc.seed, pixel_index, sample_index, 0u),
                           random_float(pc.seed, pixel_index, sample_index, 1u));
        vec3 origin = pc.camera_position_epsilon.xyz;
        vec3 dir = camera_ray(vec2(pixel) + jitter);
        vec3 throughput = vec3(1.0);
        // Density (solid angle) of the bounce that produced `dir`; 0 for camera rays.
        float bounce_pdf = 0.0;
        for (uint depth = 0u; depth < REFERENCE_MAX_DEPTH; ++depth) {
            float t;
            vec2 uv;
            int tri = trace_ray(origin, dir, eps, 1e30, false, t, uv);
            if (tri < 0) break;
            Triangle corners = triangles[tri];
            vec3 a = vertices[corners.x].position.xyz;
            vec3 b = vertices[corners.y].position.xyz;
            vec3 c = vertices[corners.z].position.xyz;
            vec3 p = origin + dir * t;
            vec3 ng = normalize(cross(b - a, c - a));
            vec3 ns = shading_normal(vertices[corners.x].normal.xyz * (1.0 - uv.x - uv.y)
                                     + vertices[corners.y].normal.xyz * uv.x
                                     + vertices[corners.z].normal.xyz * uv.y, ng);
            // Emission leaves the winding's front face (or both faces of a two-sided material).
            float cos_emit = -dot(ng, dir);
            if (dot(ng, dir) > 0.0) ng = -ng;  // two-sided reflection: face the incoming ray
            if (dot(ns, ng) < 0.0) ns = -ns;
            Material m = materials[corners.w];
            vec2 texcoord = vertex_texcoord(vertices[corners.x]) * (1.0 - uv.x - uv.y)
                          + vertex_texcoord(vertices[corners.y]) * uv.x
                          + vertex_texcoord(vertices[corners.z]) * uv.y;
            vec3 albedo = material_albedo(m, texcoord);
            vec3 specular = m.specular.rgb;
            float roughness = m.specular.w;
            float glossy = glossy_share(albedo, specular);
            vec3 view = -dir;

            bool emits = cos_emit > 0.0 || m.emission.w > 0.5;
            if (emits && any(greaterThan(m.emission.rgb, vec3(0.0)))) {
                float weight = 1.0;
                if (depth > 0u && pc.emitter_count > 0u) {
                    float light_pdf = emitter_area_pdf(m) * t * t / max(abs(cos_emit), 1e-20);
                    weight = pc.strategy == REFERENCE_STRATEGY_LIGHT ? 0.0
                           : pc.strategy == REFERENCE_STRATEGY_BSDF ? 1.0
                           : power_heuristic(bounce_pdf, light_pdf);
                }
                vec3 emitted = throughput * m.emission.rgb * weight;
                if (depth <= 1u) direct += emitted; else indirect += emitted;
            }
            if (!unlimited && depth > pc.max_bounces) break;

            vec3 shade_origin = p + ng * eps;
            for (uint l = 0u; l < pc.light_count; ++l) {
                vec3 to_light;
                float distance;
                vec3 e = light_incidence(lights[l], p, to_light, distance);
                float cos_theta = dot(ns, to_light);
                if (cos_theta <= 0.0 || dot(ng, to_light) <= 0.0 || all(equal(e, vec3(0.0)))) continue;
                // The shadow ray leaves the offset origin aimed at the light itself.
                vec3 to_light_offset = lights[l].position_kind.xyz - shade_origin;
                float reach = length(to_light_offset);
                float ts;
                vec2 uvs;
                if (trace_ray(shade_origin, to_light_offset / reach, 0.0, reach - eps, true, ts, uvs) >= 0) continue;
                vec3 reflected = throughput * albedo * INV_PI * e * cos_theta;
                if (glossy > 0.0) reflected += throughput * e * glossy_cos(specular, roughness, ns, to_light, view);
                if (depth == 0u) direct += reflected; else indirect += reflected;
            }

            if (pc.emitter_count > 0u && pc.strategy != REFERENCE_STRATEGY_BSDF) {
                uint edim = REFERENCE_EMITTER_DIM + 3u * depth;
                float pick = random_float(pc.seed, pixel_index, sample_index, edim);
                uint lo = 0u;
                uint hi = pc.emitter_count - 1u;
                while (lo < hi) {
                    uint mid = (lo + hi) / 2u;
                    if (uintBitsToFloat(emitters[mid].y) < pick) lo = mid + 1u; else hi = mid;
                }
                Triangle e_corners = triangles[emitters[lo].x];
                vec3 ea = vertices[e_corners.x].position.xyz;
                vec3 eb = vertices[e_corners.y].position.xyz;
                vec3 ec = vertices[e_corners.z].position.xyz;
                float su = sqrt(random_float(pc.seed, pixel_index, sample_index, edim + 1u));
                float v2 = random_float(pc.seed, pixel_index, sample_index, edim + 2u);
                vec3 q = ea * (1.0 - su) + eb * (su * (1.0 - v2)) + ec * (su * v2);
                vec3 en = normalize(cross(eb - ea, ec - ea));
                Material em = materials[e_corners.w];
                vec3 d = q - shade_origin;
                float dist2 = dot(d, d);
                float dist = sqrt(dist2);
                vec3 wi = d / dist;
                float cos_s = dot(ns, wi);
                float cos_e = -dot(en, wi);
                if (em.emission.w > 0.5) cos_e = abs(cos_e);
                if (cos_s > 0.0 && dot(ng, wi) > 0.0 && cos_e > 0.0) {
                    float ts;
                    vec2 uvs;
                    if (trace_ray(shade_origin, wi, 0.0, dist - eps, true, ts, uvs) < 0) {
                        float light_pdf = emitter_area_pdf(em) * dist2 / cos_e;
                        float bsdf_pdf = glossy > 0.0
                            ? (1.0 - glossy) * cos_s * INV_PI + glossy * glossy_pdf(roughness, ns, wi, view)
                            : cos_s * INV_PI;
                        float weight = pc.strategy == REFERENCE_STRATEGY_MIS
                                     ? power_heuristic(light_pdf, bsdf_pdf) : 1.0;
                        vec3 reflected = throughput * albedo * INV_PI * em.emission.rgb
                                       * (cos_s * weight / light_pdf);
                        if (glossy > 0.0) {
                            reflected += throughput * glossy_cos(specular, roughness, ns, wi, view)
                                       * em.emission.rgb * (weight / light_pdf);
                        }
                        if (depth == 0u) direct += reflected; else indirect += reflected;
                    }
                }
            }

            // The bounce out of the last allowed reflection only looks for emission.
            if (!unlimited && depth == pc.max_bounces && pc.has_emission == 0u) break;
            uint dim = 2u + 3u * depth;
            float u1 = random_float(pc.seed, pixel_index, sample_index, dim);
            float u2 = random_float(pc.seed, pixel_index, sample_index, dim + 1u);
            vec3 next;
            if (u1 < glossy) {
                vec3 t, b;
                orthonormal_basis(ns, t, b);
                next = sample_glossy(roughness, t, b, ns, view, u1 / glossy, u2);
            } else {
                next = sample_cosine_hemisphere(ns, glossy > 0.0 ? (u1 - glossy) / (1.0 - glossy) : u1, u2);
            }
            if (dot(next, ng) <= 0.0) break;
            if (glossy > 0.0) {
                // One sample of the mixture: the whole BRDF over the mixture's density.
                float cos_n = dot(ns, next);
                if (cos_n <= 0.0) break;
                bounce_pdf = (1.0 - glossy) * cos_n * INV_PI + glossy * glossy_pdf(roughness, ns, next, view);
                // A normal facing away from the view (shading normals) can be drawn where the
                // density is 0 when the lobe is all there is.
                if (bounce_pdf <= 0.0) break;
                throughput *= (albedo * INV_PI * cos_n + glossy_cos(specular, roughness, ns, next, view)) / bounce_pdf;
            } else {
                bounce_pdf = dot(ns, next) * INV_PI;
                throughput *= albedo;
            }
            if (unlimited && depth >= pc.rr_start) {
                float survive = min(max(max(throughput.r, throughput.g), throughput.b), 0.95);
                if (random_float(pc.seed, pixel_index, sample_index, dim + 2u) >= survive) break;
                throughput /= survive;
            }
            if (all(equal(throughput, vec3(0.0)))) break;
            origin = shade_origin;
            dir = next;
        }
    }
    direct_sum[pixel_index] += vec4(direct, 0.0);
    indirect_sum[pixel_index] += vec4(indirect, 0.0);
}
