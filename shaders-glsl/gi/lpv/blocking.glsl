#ifndef VKGI_LPV_BLOCKING_GLSL
#define VKGI_LPV_BLOCKING_GLSL
// The blocking function of the geometry lattice (src/gi/lpv/geometry.rs
// GeometryLattice::blocking), selected by GEOMETRY_WORDS, the words per cell:
// 1: the thesis's SH lobe B, which blocks ⟨B|Γ⟩ of a transfer;
// 3: the projected-area model of src/gi/lpv/projected.rs (normal tensor M, outward moment V, axis
//    moments S as (Mxx, Myy, Mzz, Mxy), (Mxz, Myz, Vx, Vy), (Vz, Sx, Sy, Sz)), which blocks
//    ½(min(√(tr M · oᵀMo), S·|o|) + V·o) of the transfer to the neighbour at offset o: the area the
//    surfaces show the direction of travel times the distance travelled;
// 4: the visibility model of src/gi/lpv/visibility.rs: 13 entries per cell, 1 where the segment
//    between the centres of the cell and its upper-half neighbour crosses a surface.

layout(constant_id = 4) const uint GEOMETRY_WORDS = 1u;

// 0 for a step that blocks nothing (a frame's first, which the thesis leaves unblocked:
// src/gi/lpv/technique.rs): it reads no geometry and evaluates no blocking. A constant, so that
// they are compiled away; a factor of 0 would leave lavapipe reading and computing them.
layout(constant_id = 11) const uint BLOCKS = 1u;

// The geometry words a step reads per cell: none where it blocks nothing.
const uint GEOMETRY_READ_WORDS = BLOCKS != 0u ? GEOMETRY_WORDS : 0u;

struct GeometryWords {
    vec4 w[4];  // the first GEOMETRY_WORDS hold the cell's words, the rest zero
};

GeometryWords no_geometry() {
    return GeometryWords(vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0)));
}

GeometryWords mean_geometry(GeometryWords a, GeometryWords b) {
    GeometryWords m;
    [[unroll]] for (int i = 0; i < 4; ++i) m.w[i] = 0.5 * (a.w[i] + b.w[i]);
    return m;
}

// How much of the transfer with transfer vector `transfer` to the neighbour at `offset` the
// geometry blocks, from the words of its source and its destination, before the clamp to [0, 1].
float blocking_of(GeometryWords source, GeometryWords destination, vec4 transfer, ivec3 offset) {
    if (GEOMETRY_WORDS == 4u) {
        int i = (offset.x + 1) + 3 * (offset.y + 1) + 9 * (offset.z + 1);
        int k = i > 13 ? i - 14 : 12 - i;
        vec4 word = i > 13 ? source.w[k / 4] : destination.w[k / 4];
        return word[k % 4];
    }
    if (GEOMETRY_WORDS == 3u) {
        vec4 m = source.w[0];
        vec4 mv = source.w[1];
        vec4 vs = source.w[2];
        vec3 o = vec3(offset);
        float trace = m.x + m.y + m.z;
        float along = dot(o * o, m.xyz) + 2.0 * (o.x * o.y * m.w + o.x * o.z * mv.x + o.y * o.z * mv.y);
        float tensor = sqrt(max(trace * along, 0.0));
        float axes = dot(vs.yzw, abs(o));
        return 0.5 * (min(tensor, axes) + dot(vec3(mv.zw, vs.x), o));
    }
    return dot(source.w[0], transfer);
}

// The share of a transfer that passes geometry blocking `blocked` of it (blocking_of): all of it
// where the step blocks nothing.
float passing_share(float blocked) {
    return BLOCKS != 0u ? clamp(1.0 - blocked, 0.0, 1.0) : 1.0;
}

#endif
