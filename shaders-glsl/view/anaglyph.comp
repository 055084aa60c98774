#version 460
// A stereo pair as a red-cyan anaglyph into a tile of the window image: red from the left eye's
// tone-mapped view, green and blue from the right eye's, each view scaled to the tile (nearest
// texel, as the blits of the other layouts). src/cave/stereo.rs mixes the same on the CPU for
// screenshots.

layout(local_size_x = IMAGE_WORKGROUP, local_size_y = IMAGE_WORKGROUP) in;

layout(binding = ANAGLYPH_LEFT, rgba8) readonly uniform image2D left_eye;
layout(binding = ANAGLYPH_RIGHT, rgba8) readonly uniform image2D right_eye;
layout(binding = ANAGLYPH_TARGET, rgba8) writeonly uniform image2D target;

layout(push_constant) uniform Push {
    ivec2 origin;    // the tile's corner in the target
    ivec2 tile;      // the tile's size
    ivec2 view_size; // both views' size
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, pc.tile))) return;
    ivec2 texel = min((pixel * pc.view_size) / pc.tile, pc.view_size - 1);
    vec4 left = imageLoad(left_eye, texel);
    vec4 right = imageLoad(right_eye, texel);
    imageStore(target, pc.origin + pixel, vec4(left.r, right.g, right.b, 1.0));
}
