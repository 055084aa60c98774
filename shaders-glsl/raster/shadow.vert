#version 460
// Depth-only rendering of the scene from one shadow view (vertex pulling, no vertex input).
#include "common/scene.glsl"

layout(binding = RASTER_VERTICES, std430) readonly buffer Vertices { Vertex vertices[]; };

layout(push_constant) uniform Push {
    mat4 view_projection;
} pc;

void main() {
    gl_Position = pc.view_projection * vec4(vertices[gl_VertexIndex].position.xyz, 1.0);
}
