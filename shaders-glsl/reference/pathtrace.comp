#version 460
// The reference path tracer: Lambertian surfaces, punctual lights by next-event estimation,
// emissive surfaces by cosine-weighted bounces. One invocation per pixel adds `samples` samples
// to the direct and indirect sums. src/reference/cpu.rs is the same estimator on the CPU.
//
// Light transport kept: with a bounce limit B, paths reflect at most B + 1 times (B = 0: direct
// light only; B = 1: direct and one indirect bounce); unlimited paths end by Russian roulette
// after `rr_start` bounces. "Direct" = emission seen by the camera, and light reflected once.
#include "common/math.glsl"
#include "common/scene.glsl"
#include "common/lights.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
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
} pc;

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
            if (dot(ng, dir) > 0.0) ng = -ng;  // two-sided: face the incoming ray
            if (dot(ns, ng) < 0.0) ns = -ns;
            Material m = materials[corners.w];

            vec3 emitted = throughput * m.emission.rgb;
            if (depth <= 1u) direct += emitted; else indirect += emitted;
            if (!unlimited && depth > pc.max_bounces) break;

            vec3 shade_origin = p + ng * eps;
            for (uint l = 0u; l < pc.light_count; ++l) {
                vec3 to_light;
                float distance;
                vec3 e = light_incidence(lights[l], p, to_light, distance);
                float cos_theta = dot(ns, to_light);
                if (cos_theta <= 0.0 || dot(ng, to_light) <= 0.0 || all(equal(e, vec3(0.0)))) continue;
                float ts;
                vec2 uvs;
                if (trace_ray(shade_origin, to_light, 0.0, distance - 2.0 * eps, true, ts, uvs) >= 0) continue;
                vec3 reflected = throughput * m.albedo.rgb * INV_PI * e * cos_theta;
                if (depth == 0u) direct += reflected; else indirect += reflected;
            }

            // The bounce out of the last allowed reflection only looks for emission.
            if (!unlimited && depth == pc.max_bounces && pc.has_emission == 0u) break;
            uint dim = 2u + 3u * depth;
            vec3 next = sample_cosine_hemisphere(ns,
                random_float(pc.seed, pixel_index, sample_index, dim),
                random_float(pc.seed, pixel_index, sample_index, dim + 1u));
            if (dot(next, ng) <= 0.0) break;
            throughput *= m.albedo.rgb;
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
