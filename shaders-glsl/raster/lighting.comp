#version 460
// Deferred direct lighting as a compute pass (raster/direct.glsl): any number of lights, read
// from their buffers, into the linear HDR target. Scenes whose shared lights fit the fragment
// form's varyings are lit by raster/lighting.frag instead (src/render/passes.rs).
#include "raster/direct.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = LIGHTING_LIGHTS, std430) readonly buffer Lights { Light lights[]; };
layout(binding = LIGHTING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { ShadowView shadow_views[]; };
layout(binding = LIGHTING_HDR_OUT, rgba32f) writeonly uniform image2D hdr_out;

// Emission plus the reflected light of every shadowed punctual light at pixel `pixel`.
vec3 direct_radiance(ivec2 pixel, vec4 position) {
    Surface s = load_surface(pixel, position.xyz);
    vec3 irradiance = vec3(0.0);
    vec3 reflected = vec3(0.0);
    if (SHARED_LIGHTS > 0u) {
        // Each shared light and its shadow views read at indices every pixel shares.
        [[unroll]] for (uint i = 0u; i < SHARED_LIGHTS; ++i) {
            uint first = shared_first_view(i);
            uint last = shared_last_view(i);
            ShadowView views[SHARED_LIGHT_VIEWS];
            [[unroll]] for (uint f = 0u; f < SHARED_LIGHT_VIEWS; ++f) views[f] = shadow_views[first + min(f, last)];
            add_shared_light(i, lights[i], views, s, irradiance, reflected);
        }
    } else {
        for (uint i = 0u; i < pc.light_count; ++i) {
            Light light = lights[i];
            uint view = shadow_view_index(light, s.p);
            add_light(light, shadow_views[view], view, s, irradiance, reflected);
        }
    }
    return shaded(s, position, irradiance, reflected);
}

void main() {
    // No early return: lavapipe would put everything after it in a branch. Invocations past
    // the image's edge shade its last row or column and store nothing.
    uvec2 id = gl_GlobalInvocationID.xy;
    ivec2 pixel = ivec2(min(id, pc.size - 1u));
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 radiance = direct_radiance(pixel, position);
    if (all(lessThan(id, pc.size))) imageStore(hdr_out, pixel, vec4(radiance, 1.0));
}
