#ifndef VKGI_SCENE_GLSL
#define VKGI_SCENE_GLSL
// Scene layouts; the Rust side is src/scene/gpu.rs (GpuVertex, GpuMaterial).

struct Vertex {
    vec4 position;  // xyz, w = 1
    vec4 normal;    // xyz shading normal, w = 0
};

struct Material {
    vec4 albedo;    // rgb diffuse albedo
    vec4 emission;  // rgb emitted radiance
};

#endif
