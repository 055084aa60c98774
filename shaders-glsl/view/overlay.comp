#version 460
// The window's text overlay: a darkened box with white text, blended onto the composed window
// image. The host rasterises the text into a mask (one uint per pixel: OVERLAY_* values).

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = OVERLAY_TARGET, rgba8) uniform image2D target;
layout(binding = OVERLAY_MASK, std430) readonly buffer Mask { uint mask[]; };

layout(push_constant) uniform Push {
    uvec2 origin;
    uvec2 size;
    uvec2 target_size;
} pc;

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(local, pc.size))) return;
    uvec2 pixel = pc.origin + local;
    if (any(greaterThanEqual(pixel, pc.target_size))) return;
    uint m = mask[local.y * pc.size.x + local.x];
    if (m == OVERLAY_CLEAR) return;
    vec4 c = imageLoad(target, ivec2(pixel));
    vec3 rgb = m == OVERLAY_TEXT ? vec3(1.0) : c.rgb * 0.3;
    imageStore(target, ivec2(pixel), vec4(rgb, 1.0));
}
