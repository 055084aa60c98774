//! Binding numbers of the passes in src/gi/shared/, seen by every shader under
//! shaders-glsl/gi/ (build.rs reads them from here).

crate::shared_constants! {
    // ---- reflective shadow maps (shaders-glsl/gi/shared/rsm.vert and rsm.frag; the vertex
    // stage is the G-buffer's, bound with RASTER_VERTICES, RASTER_TRIANGLES and
    // RASTER_MATERIALS) ----
    RSM_LIGHTS: u32 = 3;
    RSM_VIEWS: u32 = 4;
    RSM_TEXTURES: u32 = 5;
}
