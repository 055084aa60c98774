#ifndef VKGI_SCENE_GLSL
#define VKGI_SCENE_GLSL
// Scene layouts; the Rust side is src/scene/gpu.rs (GpuVertex, GpuMaterial).

struct Vertex {
    vec4 position;  // xyz, w = texture coordinate u
    vec4 normal;    // xyz unit shading normal, or zero where the mesh has none; w = texture v
};

vec2 vertex_texcoord(Vertex v) {
    return vec2(v.position.w, v.normal.w);
}

// A triangle: xyz = its three vertex indices (winding order), w = its material.
#define Triangle uvec4

// The shading normal from interpolated vertex normals, or the face normal where they vanish
// (vertices without normals); src/scene/mod.rs Mesh::shading_normal is the same rule.
vec3 shading_normal(vec3 interpolated, vec3 face) {
    return dot(interpolated, interpolated) > 1e-12 ? normalize(interpolated) : face;
}

struct Material {
    vec4 albedo;    // rgb diffuse albedo (factor), w = 1 + albedo texture index, 0 for none
    vec4 emission;  // rgb emitted radiance, w = 1 when emitted from both faces (else the front)
    vec4 specular;  // rgb reflectance of the glossy lobe (common/brdf.glsl), w = roughness
};

#endif
