#version 460
// The full-screen triangle of the lookup (lpv/lookup.frag), which hands the lookup's push
// constants to every fragment as flat varyings: read in the fragment shader, lavapipe reads
// them lane by lane (docs/performance.md).
#include "gi/lpv/lookup_fields.glsl"

layout(location = 0) flat out vec4 fields[FIELD_WORDS];

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
    [[unroll]] for (int f = 0; f < 2; ++f) {
        fields[3 * f] = pc.origin_cell[f];
        fields[3 * f + 1] = vec4(pc.dims[f]);
        fields[3 * f + 2] = pc.scale_offset[f];
    }
}
