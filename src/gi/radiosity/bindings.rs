//! Binding numbers of the radiosity passes, seen only by shaders-glsl/gi/radiosity/. A
//! resource has the same number in every pass that binds it.

crate::shared_constants! {
    RAD_SURFACES: u32 = 0;
    RAD_ELEMENTS: u32 = 1;
    RAD_UNSHOT: u32 = 2;
    RAD_DIRECT: u32 = 3;
    RAD_INDIRECT: u32 = 4;
    RAD_STATS: u32 = 5;
    RAD_EMISSION_UNSHOT: u32 = 6;
    RAD_SHOT: u32 = 7;
    RAD_LOCATIONS: u32 = 8;
    RAD_ITEM_VERTICES: u32 = 9;
    RAD_ITEM_TRIANGLES: u32 = 10;
    RAD_ITEM_IDS: u32 = 11;
    RAD_ITEM_DISTANCE: u32 = 12;
    RAD_TRIANGLE_PATCH: u32 = 13;
    RAD_PATCH_SURFACES: u32 = 14;
    RAD_PATCH_NORMALS: u32 = 15;
    RAD_TRIANGLE_IDS: u32 = 16;
    RAD_GBUFFER_POSITION: u32 = 17;
    RAD_GBUFFER_ALBEDO: u32 = 18;
    RAD_HDR: u32 = 19;
    RAD_IMPORTANCE: u32 = 20;
    RAD_IMPORTANCE_UNSHOT: u32 = 21;
    RAD_IMPORTANCE_RECEIVED: u32 = 22;
    RAD_IMPORTANCE_STATS: u32 = 23;
    RAD_VISIBLE: u32 = 24;
    RAD_TABLE: u32 = 25;
    RAD_TABLE_LOCATIONS: u32 = 26;
    RAD_DELIVERY: u32 = 27;
    RAD_TABLE_COLUMNS: u32 = 28;
}
