#ifndef VKGI_LPV_LOOKUP_FIELDS_GLSL
#define VKGI_LPV_LOOKUP_FIELDS_GLSL
// The lookup's fields (one lattice, or ILPV's near and far lattices) as src/gi/lpv/lookup.rs
// pushes them, and as lpv/lookup.vert hands them to lpv/lookup.frag: per field three flat words,
// (origin, cell size), the lattice's cells (as floats) and (scale, offset).
#extension GL_EXT_control_flow_attributes : require

layout(push_constant) uniform Push {
    vec4 origin_cell[2];   // per field: xyz lattice origin, w cell size
    ivec4 dims[2];
    vec4 scale_offset[2];  // x: 1 / (pi cell²) times the method's scale; y: the offset in cells
} pc;

const int FIELD_WORDS = 6;

#endif
