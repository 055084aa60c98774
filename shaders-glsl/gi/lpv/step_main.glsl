#ifndef VKGI_LPV_STEP_MAIN_GLSL
#define VKGI_LPV_STEP_MAIN_GLSL
// The entry point of a propagation step: the including step defines `Light gather(ivec3 cell)`
// (the cell's new light from its sources, read through tile.glsl) and
// `void store(ivec3 cell, Light light)`; tile.glsl's mode decides how cells are walked.

void main() {
    load_step_constants();
#if LPV_COLUMN
    // The bundle's first column, and the first cell of its piece of the column.
    ivec3 first = ivec3(gl_GlobalInvocationID.xy * BUNDLE, gl_GlobalInvocationID.z * COLUMN);
    if (!lattice_inside(first, pc.dims.xyz)) return;
    load_plane(first, -1);
    load_plane(first, 0);
    // Every thread of a workgroup shares its z range, so the loop ends for all at once.
    for (uint k = 0u; k < COLUMN; ++k) {
        ivec3 origin = first + ivec3(0, 0, k);
        if (origin.z >= pc.dims.z) break;
        load_plane(origin, 1);
        [[unroll]] for (int y = 0; y < BUNDLE; ++y) {
            [[unroll]] for (int x = 0; x < BUNDLE; ++x) {
                bundle_member = ivec2(x, y);
                ivec3 cell = origin + ivec3(x, y, 0);
                Light light = gather(cell);
                // A bundle over the lattice's last column or row computes cells past it.
                if (all(lessThan(cell.xy, pc.dims.xy))) store(cell, light);
            }
        }
        advance_column();
    }
#else
    prepare_sources();
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!lattice_inside(cell, pc.dims.xyz)) return;
    store(cell, gather(cell));
#endif
}

#endif
