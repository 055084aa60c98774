#version 460
// LightWave per pixel (vkgi's improvement, spec 002 §9): the gather evaluated at every pixel's
// own position and normal, so the indirect light does not depend on the mesh's tessellation.
#include "gi/lightwave/composite.glsl"

void prepare_gather(ivec2 pixel, vec3 p, vec3 n) {}

float gathered(uint l, vec3 p, vec3 n) {
    return gather(l, p, n);
}
