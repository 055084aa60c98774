#version 460
// Direct lighting with the half-resolution lookup's light (--lookup-resolution half): the
// frame's direct radiance (raster/lighting_pixel.glsl, its vertex shader raster/lighting.vert)
// plus the upsampled light (lpv/upsample.glsl) times albedo, written once to the HDR image; the
// same sum as direct lighting followed by lpv/upsample.frag.
#include "raster/lighting_pixel.glsl"
#include "gi/lpv/upsample.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position;
    Surface s;
    vec3 direct = direct_radiance(pixel, position, s);
    vec3 indirect = s.albedo * upsampled_light(pixel, position.xyz, s.n, pc.camera_position.xyz);
    // Background pixels (w = 0) get no indirect light.
    out_radiance = vec4(direct + (position.w != 0.0 ? indirect : vec3(0.0)), 1.0);
}
