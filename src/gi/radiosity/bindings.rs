//! Binding numbers of the radiosity passes, seen only by shaders-glsl/gi/radiosity/. A
//! resource has the same number in every pass that binds it, from 16 on: the display drawn
//! inside direct lighting (lit_display.frag) binds direct lighting's LIGHTING_ bindings (0-8)
//! beside them.

crate::shared_constants! {
    RAD_SURFACES: u32 = 16;
    RAD_ELEMENTS: u32 = 17;
    RAD_UNSHOT: u32 = 18;
    RAD_DIRECT: u32 = 19;
    RAD_INDIRECT: u32 = 20;
    RAD_STATS: u32 = 21;
    RAD_EMISSION_UNSHOT: u32 = 22;
    RAD_SHOT: u32 = 23;
    RAD_LOCATIONS: u32 = 24;
    RAD_ITEM_VERTICES: u32 = 25;
    RAD_ITEM_TRIANGLES: u32 = 26;
    RAD_ITEM_IDS: u32 = 27;
    RAD_ITEM_DISTANCE: u32 = 28;
    RAD_TRIANGLE_SIDES: u32 = 29;
    RAD_TRIANGLE_IDS: u32 = 32;
    RAD_GBUFFER_POSITION: u32 = 33;
    RAD_GBUFFER_ALBEDO: u32 = 34;
    RAD_HDR: u32 = 35;
    RAD_IMPORTANCE: u32 = 36;
    RAD_IMPORTANCE_UNSHOT: u32 = 37;
    RAD_IMPORTANCE_RECEIVED: u32 = 38;
    RAD_IMPORTANCE_STATS: u32 = 39;
    RAD_VISIBLE: u32 = 40;
    RAD_TABLE: u32 = 41;
    RAD_TABLE_LOCATIONS: u32 = 42;
    RAD_DELIVERY: u32 = 43;
    RAD_TABLE_COLUMNS: u32 = 44;
    /// The lit display's specialisation constant: add the ambient term of light still unshot
    /// (direct lighting's own constants are 0-3).
    RAD_AMBIENT_CONSTANT: u32 = 8;
}
