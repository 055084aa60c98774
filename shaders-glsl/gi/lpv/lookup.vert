#version 460
// The full-screen triangle of the lookup (lpv/lookup.frag), which hands the lookup's fields to
// every fragment as flat varyings (lpv/lookup_fields.glsl): read in the fragment shader, lavapipe
// reads them lane by lane (docs/performance.md). At the far plane, as common/fullscreen.vert.
#include "gi/lpv/lookup_fields.glsl"

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
    write_field_words();
}
