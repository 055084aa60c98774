#version 460
// The surface seen, and its distance from the shooting location.
layout(location = 0) flat in uint in_surface;
layout(location = 1) in float in_distance;
layout(location = 0) out uint out_surface;
layout(location = 1) out float out_distance;

void main() {
    out_surface = in_surface;
    out_distance = in_distance;
}
