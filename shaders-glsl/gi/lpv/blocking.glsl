#ifndef VKGI_LPV_BLOCKING_GLSL
#define VKGI_LPV_BLOCKING_GLSL
// The blocking function of a geometry-lattice cell (src/gi/lpv/geometry.rs
// GeometryLattice::blocking). GEOMETRY_WORDS words per cell: 1 holds the thesis's SH lobe B,
// which blocks ⟨B|Γ⟩ of a transfer; 3 hold the projected-area model of src/gi/lpv/projected.rs
// (normal tensor M, outward moment V, axis moments S as (Mxx, Myy, Mzz, Mxy),
// (Mxz, Myz, Vx, Vy), (Vz, Sx, Sy, Sz)), which blocks ½(min(√(tr M · oᵀMo), S·|o|) + V·o) of the
// transfer to the neighbour at offset o: the area the surfaces show the direction of travel
// times the distance travelled, one-way for surfaces facing the void.

layout(constant_id = 4) const uint GEOMETRY_WORDS = 1u;

struct GeometryWords {
    vec4 first;
    vec4 second;  // zero with one word per cell
    vec4 third;   // zero with one word per cell
};

GeometryWords no_geometry() {
    return GeometryWords(vec4(0.0), vec4(0.0), vec4(0.0));
}

GeometryWords mean_geometry(GeometryWords a, GeometryWords b) {
    return GeometryWords(0.5 * (a.first + b.first), 0.5 * (a.second + b.second),
                         0.5 * (a.third + b.third));
}

// How much of the transfer with transfer vector `transfer` to the neighbour at `offset` the
// geometry blocks, before the clamp to [0, 1].
float blocking_of(GeometryWords g, vec4 transfer, vec3 offset) {
    if (GEOMETRY_WORDS == 3u) {
        vec4 m = g.first;
        vec4 mv = g.second;
        vec4 vs = g.third;
        vec3 o = offset;
        float trace = m.x + m.y + m.z;
        float along = dot(o * o, m.xyz) + 2.0 * (o.x * o.y * m.w + o.x * o.z * mv.x + o.y * o.z * mv.y);
        float tensor = sqrt(max(trace * along, 0.0));
        float axes = dot(vs.yzw, abs(o));
        return 0.5 * (min(tensor, axes) + dot(vec3(mv.zw, vs.x), o));
    }
    return dot(g.first, transfer);
}

#endif
