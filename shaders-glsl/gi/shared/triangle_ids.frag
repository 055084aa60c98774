#version 460
// The triangle index + 1 (0 where nothing was drawn).
layout(location = 0) flat in uint in_triangle;
layout(location = 0) out uint out_id;

void main() {
    out_id = in_triangle + 1u;
}
