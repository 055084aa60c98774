#version 460
// Direct lighting and the radiosity display in one pass: the frame's direct radiance
// (raster/lighting_pixel.glsl, drawn with raster/lighting.vert) plus albedo / pi times the
// solution's indirect irradiance at the surface it read (radiosity/display.glsl), written once
// to the HDR image over the pixels a surface covers; the same sum as direct lighting followed
// by radiosity/display.comp.
#include "raster/lighting_pixel.glsl"
#include "gi/radiosity/display.glsl"

// Add the ambient term of light still unshot (--radiosity-ambient).
layout(constant_id = RAD_AMBIENT_CONSTANT) const bool AMBIENT = true;

layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position;
    Surface s;
    vec3 direct = direct_radiance(pixel, position, s);
    vec3 irradiance;
    bool shown = display_irradiance(pixel, position.xyz, pc.camera_position.xyz, AMBIENT, irradiance);
    // Background pixels (w = 0) get no indirect light.
    bool lit = position.w != 0.0 && shown;
    out_radiance = vec4(direct + (lit ? s.albedo * irradiance * INV_PI : vec3(0.0)), 1.0);
}
