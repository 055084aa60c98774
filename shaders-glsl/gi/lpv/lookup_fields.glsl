#ifndef VKGI_LPV_LOOKUP_FIELDS_GLSL
#define VKGI_LPV_LOOKUP_FIELDS_GLSL
// The vertex side of the lookup: its fields (one lattice, or ILPV's near and far lattices) as
// src/gi/lpv/lookup.rs writes them into a buffer once, handed to every fragment as
// LOOKUP_FIELD_WORDS flat varyings from location LOOKUP_FIELDS_LOCATION on (0 unless the
// shader defines it), or read from the buffer by the compute form (LOOKUP_COMPUTE): per field
// (origin, cell size), the lattice's cells and 1 where its texels hold them in columns (as
// floats), and (scale, offset). lpv/lookup_light.glsl is the fragment side.
#extension GL_EXT_control_flow_attributes : require

#ifndef LOOKUP_FIELDS_LOCATION
#define LOOKUP_FIELDS_LOCATION 0
#endif
// 1 in the compute form (lpv/lookup_compute.glsl), which reads the words itself.
#ifndef LOOKUP_COMPUTE
#define LOOKUP_COMPUTE 0
#endif

layout(binding = LOOKUP_FIELDS, std430) readonly buffer Fields {
    vec4 origin_cell[2];   // per field: xyz lattice origin, w cell size
    ivec4 dims[2];         // per field: xyz cells, w 1 where the texels hold columns
    vec4 scale_offset[2];  // x: 1 / (pi cell²) times the method's scale; y: the offset in cells
} lookup_fields;

// The fields' words as the lookup reads them (lpv/lookup_light.glsl's `fields`).
void field_words(out vec4 words[LOOKUP_FIELD_WORDS]) {
    [[unroll]] for (int f = 0; f < 2; ++f) {
        words[3 * f] = lookup_fields.origin_cell[f];
        words[3 * f + 1] = vec4(lookup_fields.dims[f]);
        words[3 * f + 2] = lookup_fields.scale_offset[f];
    }
}

#if !LOOKUP_COMPUTE
layout(location = LOOKUP_FIELDS_LOCATION) flat out vec4 fields[LOOKUP_FIELD_WORDS];

void write_field_words() {
    field_words(fields);
}
#endif

#endif
