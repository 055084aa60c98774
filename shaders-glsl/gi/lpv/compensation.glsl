#ifndef VKGI_LPV_COMPENSATION_GLSL
#define VKGI_LPV_COMPENSATION_GLSL
// ILPV's clamp compensation of one cell (src/gi/lpv/cpu.rs medium_mix and compensate_clamp in
// f64): apply the step's medium (absorption from both bands, isotropic scattering moves the
// directional band's scattered part into the DC band) and scale the cell so that one unblocked
// step, then pure transport, moves exactly the energy the medium left: by E over the energy the
// clamped transfers would move. The compensation pass (compensate.glsl) applies it to a step's
// source; a step whose result the next step propagates applies it to its result as it stores it
// (ilpv_step.glsl). The includer defines `vec4 compensation_transfer(int d)`, the transfer
// vector of neighbour d, and enables GL_EXT_control_flow_attributes.

// Cell light `cell` after the medium (`keep_dc` = 1 - λa, `keep_directional` = 1 - λa - λs),
// compensated for the clamped transfers.
vec4 compensated(vec4 cell, float keep_dc, float keep_directional) {
    vec4 l = cell * vec4(keep_dc, vec3(keep_directional));
    float moved = 0.0;
    [[unroll]] for (int d = 0; d < 26; ++d) {
        vec4 transfer = compensation_transfer(d);
        moved += max(dot(l, transfer), 0.0) * transfer.x;
    }
    return moved > 0.0 && l.x > 0.0 ? l * (l.x / moved) : l;
}

#endif
