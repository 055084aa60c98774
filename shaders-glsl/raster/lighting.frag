#version 460
// Deferred direct lighting as a fragment pass over a full-screen triangle
// (raster/lighting_pixel.glsl), for scenes whose SHARED_LIGHTS lights and their views fit the
// flat varyings raster/lighting.vert fills (src/render/passes.rs chooses). Against the compute
// form it trades the imageStore of the HDR pixel for a render target's write and reads the
// lights from varyings, the same for every fragment: the same radiance, in less time on
// lavapipe (docs/performance.md).
#include "raster/lighting_pixel.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    vec4 position;
    Surface s;
    out_radiance = vec4(direct_radiance(ivec2(gl_FragCoord.xy), position, s), 1.0);
}
