#version 460
// One triangle that covers the whole viewport (clip space -1..3), for per-pixel fragment passes,
// at the far plane (depth 1): a pass of covered pixels only (src/gpu/pipeline.rs Depth::Covered)
// tests it GREATER against the G-buffer's depth, which passes where a surface lies nearer.
void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
}
