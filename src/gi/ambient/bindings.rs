//! Binding numbers of the ambient passes, seen only by shaders-glsl/gi/ambient/.

crate::shared_constants! {
    // ---- the ambient term as a pass of its own (lookup.comp) ----
    AMBIENT_GBUFFER_POSITION: u32 = 0;
    AMBIENT_GBUFFER_ALBEDO: u32 = 1;
    AMBIENT_HDR: u32 = 2;
    // ---- inside direct lighting (lit.{vert,frag}), beside the LIGHTING_ bindings ----
    AMBIENT_IRRADIANCE: u32 = 16;
}
