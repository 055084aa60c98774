#ifndef VKGI_LPV_LOOKUP_COMPUTE_GLSL
#define VKGI_LPV_LOOKUP_COMPUTE_GLSL
// Indirect light from the lattice (lpv/lookup_light.glsl) added to the HDR image by a compute
// pass: the lookup drawn apart in the form a GPU runs (src/gpu/context.rs, PixelPasses), where
// lpv/lookup_pass.glsl is the fragment form. The same sum as that form's blend: the HDR pixel
// plus the lattices' light; background pixels (w = 0) keep theirs.
#define LOOKUP_COMPUTE 1
#include "gi/lpv/lookup_fields.glsl"
#include "gi/lpv/lookup_light.glsl"
#include "gi/lpv/lookup_surface.glsl"

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = LOOKUP_HDR, rgba32f) uniform image2D hdr;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(hdr)))) return;
    vec4 position = surface_position(pixel);
    if (position.w == 0.0) return;
    field_words(fields);
    vec3 n = surface_normal(pixel);
    vec3 albedo = surface_albedo(pixel);
    vec3 value = lattice_radiance(position.xyz, n, albedo);
    imageStore(hdr, pixel, imageLoad(hdr, pixel) + vec4(value, 0.0));
}

#endif
