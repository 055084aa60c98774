#ifndef VKGI_LPV_STEP_MAIN_GLSL
#define VKGI_LPV_STEP_MAIN_GLSL
// The entry point of a propagation step: the including step defines `Light gather(ivec3 cell)`
// (the cell's new light from its sources, read through tile.glsl; for the column kernel's
// stream, `gather_group(cell, group, own_geometry, dst)`, its terms from one plane of sources)
// and `void store(ivec3 cell, Light light)`; tile.glsl's mode decides how cells are walked.

// Whether the piece of a column from `first` lies outside the lattice, so that its thread
// returns at once. With shared rows only where the whole row does: a thread past the lattice in
// x still reads the ends of a plane's rows for its subgroup (one a lane) and its cells for the
// lanes beside it (zeros), and stores nothing.
bool walks_nothing(ivec3 first) {
#if COLUMN_SHARED_ROWS
    return first.y >= pc.dims.y || first.z >= pc.dims.z;
#else
    return !lattice_inside(first, pc.dims.xyz);
#endif
}

void main() {
    load_step_constants();
#if LPV_COLUMN && COLUMN_STREAM
    // The bundle's first column, the first cell of its piece of the column and the last.
    ivec3 first = ivec3(gl_GlobalInvocationID.xy * BUNDLE, gl_GlobalInvocationID.z * COLUMN);
    if (walks_nothing(first)) return;
    int last = min(first.z + int(COLUMN), pc.dims.z) - 1;
    // While plane p is read, each member's cell at p has the group of plane p + 1 (`nearer`),
    // the one at p + 1 those of p + 2 and p + 1 (`farther`): plane p completes the farther,
    // adds to the nearer and starts the cell at p - 1, with their own geometry.
    const int MEMBERS = BUNDLE * BUNDLE;
    Light nearer[MEMBERS];
    Light farther[MEMBERS];
    GeometryWords nearer_own[MEMBERS];
    GeometryWords farther_own[MEMBERS];
    [[unroll]] for (int m = 0; m < MEMBERS; ++m) {
        nearer[m] = no_light();
        farther[m] = no_light();
        nearer_own[m] = no_geometry();
        farther_own[m] = no_geometry();
    }
    // The plane above the piece starts its last cells (above a whole column: nothing).
    if (WHOLE_COLUMNS == 0u) load_plane(ivec3(first.xy, last + 1), 0);
    [[unroll]] for (int m = 0; m < MEMBERS; ++m) {
        bundle_member = ivec2(m % BUNDLE, m / BUNDLE);
        ivec3 cell = ivec3(first.xy + bundle_member, last);
        nearer_own[m] = own_geometry(cell);
        if (WHOLE_COLUMNS == 0u) gather_group(cell, 0, nearer_own[m], nearer[m]);
    }
    // Every thread of a workgroup shares its z range, so the loop ends for all at once.
    for (int p = last; p >= first.z; --p) {
        load_plane(ivec3(first.xy, p), 0);
        [[unroll]] for (int m = 0; m < MEMBERS; ++m) {
            bundle_member = ivec2(m % BUNDLE, m / BUNDLE);
            ivec3 cell = ivec3(first.xy + bundle_member, p);
            ivec3 up = cell + ivec3(0, 0, 1);
            ivec3 down = cell - ivec3(0, 0, 1);
            // The first plane's farther cell lies past the piece, the last one's cell at p - 1
            // before it: their terms are computed (a branch would not skip them) and not stored.
            gather_group(up, 2, farther_own[m], farther[m]);
            // A bundle over the lattice's last column or row computes cells past it.
            if (all(lessThan(cell.xy, pc.dims.xy)) && p < last) store(up, farther[m]);
            gather_group(cell, 1, nearer_own[m], nearer[m]);
            farther[m] = nearer[m];
            farther_own[m] = nearer_own[m];
            nearer_own[m] = own_geometry(down);
            nearer[m] = no_light();
            gather_group(down, 0, nearer_own[m], nearer[m]);
        }
    }
    // The plane below the piece completes its first cells (below a whole column: nothing).
    if (WHOLE_COLUMNS == 0u) load_plane(ivec3(first.xy, first.z - 1), 0);
    [[unroll]] for (int m = 0; m < MEMBERS; ++m) {
        bundle_member = ivec2(m % BUNDLE, m / BUNDLE);
        ivec3 cell = ivec3(first.xy + bundle_member, first.z);
        if (WHOLE_COLUMNS == 0u) gather_group(cell, 2, farther_own[m], farther[m]);
        if (all(lessThan(cell.xy, pc.dims.xy))) store(cell, farther[m]);
    }
#elif LPV_COLUMN
    // The bundle's first column, and the first cell of its piece of the column.
    ivec3 first = ivec3(gl_GlobalInvocationID.xy * BUNDLE, gl_GlobalInvocationID.z * COLUMN);
    if (walks_nothing(first)) return;
    // The own columns below and at the first cell (below a whole column: nothing).
    if (WHOLE_COLUMNS != 0u) {
        clear_own_columns(-1);
    } else {
        load_cells(first, -1, true, false);
    }
    load_cells(first, 0, true, false);
    // Every thread of a workgroup shares its z range, so the loop ends for all at once.
    for (uint k = 0u; k < COLUMN; ++k) {
        ivec3 origin = first + ivec3(0, 0, k);
        if (origin.z >= pc.dims.z) break;
        // This plane around the own columns, and the own columns above.
        load_around(origin);
        load_cells(origin, 1, true, false);
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
