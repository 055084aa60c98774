#version 460
// A stereo pair as a red-cyan anaglyph into the window image: red from the left eye's
// tone-mapped view, green and blue from the right eye's (src/cave/stereo.rs composes the same on
// the CPU for screenshots).

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = ANAGLYPH_LEFT, rgba8) readonly uniform image2D left_eye;
layout(binding = ANAGLYPH_RIGHT, rgba8) readonly uniform image2D right_eye;
layout(binding = ANAGLYPH_TARGET, rgba8) writeonly uniform image2D target;

layout(push_constant) uniform Push {
    ivec2 origin; // where the pair goes in the target
    ivec2 size;   // the views' size
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, pc.size))) return;
    vec4 left = imageLoad(left_eye, pixel);
    vec4 right = imageLoad(right_eye, pixel);
    imageStore(target, pc.origin + pixel, vec4(left.r, right.g, right.b, 1.0));
}
