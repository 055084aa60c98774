//! Binding numbers of the LPV passes, seen only by shaders-glsl/gi/lpv/ (build.rs reads them
//! from here).

crate::shared_constants! {
    // ---- injection ----
    INJECT_RSM_POSITION: u32 = 0;
    INJECT_RSM_NORMAL: u32 = 1;
    INJECT_RSM_FLUX: u32 = 2;
    INJECT_LATTICE_R: u32 = 3;
    INJECT_LATTICE_G: u32 = 4;
    INJECT_LATTICE_B: u32 = 5;
    INJECT_VIEWS: u32 = 6;
    RESOLVE_FIXED_R: u32 = 0;
    RESOLVE_FIXED_G: u32 = 1;
    RESOLVE_FIXED_B: u32 = 2;
    RESOLVE_LATTICE_R: u32 = 3;
    RESOLVE_LATTICE_G: u32 = 4;
    RESOLVE_LATTICE_B: u32 = 5;

    // ---- ILPV merge and clamp compensation ----
    // The blend: one channel (the _R bindings) or all three; target, current and previous
    // lattices (target and current the same one where the blend is in place).
    MERGE_TARGET_R: u32 = 0;
    MERGE_TARGET_G: u32 = 1;
    MERGE_TARGET_B: u32 = 2;
    MERGE_CURRENT_R: u32 = 3;
    MERGE_CURRENT_G: u32 = 4;
    MERGE_CURRENT_B: u32 = 5;
    MERGE_PREVIOUS_R: u32 = 6;
    MERGE_PREVIOUS_G: u32 = 7;
    MERGE_PREVIOUS_B: u32 = 8;
    // Compensation: one channel (the _R bindings) or all three; the cells written as storage
    // and, where the lattices have texel views, read as texels.
    COMPENSATE_CELLS_R: u32 = 0;
    COMPENSATE_CELLS_G: u32 = 1;
    COMPENSATE_CELLS_B: u32 = 2;
    COMPENSATE_READ_R: u32 = 3;
    COMPENSATE_READ_G: u32 = 4;
    COMPENSATE_READ_B: u32 = 5;
    COMPENSATE_NEIGHBOURS: u32 = 6;

    // ---- propagation: 26-neighbour ILPV and 6-neighbour LPV, one colour channel a dispatch
    // (the _R bindings) or all three ----
    STEP_SOURCE_R: u32 = 0;
    STEP_SOURCE_G: u32 = 1;
    STEP_SOURCE_B: u32 = 2;
    STEP_DESTINATION_R: u32 = 3;
    STEP_DESTINATION_G: u32 = 4;
    STEP_DESTINATION_B: u32 = 5;
    STEP_ACCUMULATION_R: u32 = 6;
    STEP_ACCUMULATION_G: u32 = 7;
    STEP_ACCUMULATION_B: u32 = 8;
    // The accumulation read as texels (the kernels that read their sources as texels).
    STEP_ACCUMULATION_READ_R: u32 = 9;
    STEP_ACCUMULATION_READ_G: u32 = 10;
    STEP_ACCUMULATION_READ_B: u32 = 11;
    STEP_GEOMETRY: u32 = 12;
    // ILPV's 26 neighbours, LPV's 6 axes.
    STEP_CONSTANTS: u32 = 13;

    // ---- lookup ----
    // The G-buffer (lpv/lookup.frag; inside direct lighting, lpv/lit_lookup.frag reads it
    // through direct lighting's bindings, LIGHTING_*, which the numbers below stay clear of).
    LOOKUP_GBUFFER_POSITION: u32 = 0;
    LOOKUP_GBUFFER_NORMAL: u32 = 1;
    LOOKUP_GBUFFER_ALBEDO: u32 = 2;
    LOOKUP_LATTICE_R: u32 = 16;
    LOOKUP_LATTICE_G: u32 = 17;
    LOOKUP_LATTICE_B: u32 = 18;
    // Two scales: the far field's lattices (a one-lattice lookup binds its own here too).
    LOOKUP_FAR_LATTICE_R: u32 = 19;
    LOOKUP_FAR_LATTICE_G: u32 = 20;
    LOOKUP_FAR_LATTICE_B: u32 = 21;
    // The fields' constants (lpv/lookup_fields.glsl), and their flat varyings.
    LOOKUP_FIELDS: u32 = 22;
    LOOKUP_FIELD_WORDS: u32 = 6;
    // --lookup-resolution half: the quarter-size image of the lattices' light (lpv/upsample.glsl).
    LOOKUP_HALF_LIGHT: u32 = 23;
    // The compute form of the lookup apart (lpv/lookup_compute.glsl): the HDR image it adds to.
    LOOKUP_HDR: u32 = 24;
    // The upsample's weights (lpv/upsample.glsl and its f64 mirror, src/gi/lpv/upsample.rs):
    // the relative distance difference at which a texel's weight reaches zero, the least cosine
    // of a pixel's normal and ray it counts, the sum of weights below which no texel is alike,
    // the margin by which a later texel must be more alike to be the most alike, and the
    // distance a texel without a surface holds.
    UPSAMPLE_DISTANCE_TOLERANCE: f32 = 0.05;
    UPSAMPLE_MIN_FACING: f32 = 0.1;
    UPSAMPLE_LEAST_WEIGHT: f32 = 0.001;
    UPSAMPLE_MISS_MARGIN: f32 = 0.001;
    UPSAMPLE_NO_SURFACE: f32 = 1e30;
    // The specialisation constant of the number of fields, clear of direct lighting's.
    LOOKUP_FIELDS_CONSTANT: u32 = 8;
    // The specialisation constant of the lattices' cell order (lpv/lattice.glsl, CellOrder),
    // clear of the steps', the injection's and the lookups' own.
    CELLS_IN_COLUMNS_CONSTANT: u32 = 12;
}
