//! Binding numbers of the ambient lookup, seen only by shaders-glsl/gi/ambient/.

crate::shared_constants! {
    AMBIENT_GBUFFER_POSITION: u32 = 0;
    AMBIENT_GBUFFER_ALBEDO: u32 = 1;
    AMBIENT_HDR: u32 = 2;
}
