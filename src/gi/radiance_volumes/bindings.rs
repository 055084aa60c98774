//! Binding numbers and constants of the radiance-volume passes, seen only by
//! shaders-glsl/gi/radiance_volumes/. A resource has the same number in every pass that binds it.

crate::shared_constants! {
    RV_ADDRESS: u32 = 0;
    RV_CACHES: u32 = 1;
    RV_STATE: u32 = 2;
    RV_VALS: u32 = 4;
    RV_GBUFFER_POSITION: u32 = 5;
    RV_GBUFFER_NORMAL: u32 = 6;
    RV_GBUFFER_ALBEDO: u32 = 7;
    RV_HDR: u32 = 8;
    RV_RSM_POSITION: u32 = 9;
    RV_RSM_NORMAL: u32 = 10;
    RV_RSM_FLUX: u32 = 11;
    RV_SHADOW_VIEWS: u32 = 12;
    RV_VERTICES: u32 = 13;
    RV_TRIANGLES: u32 = 14;
    RV_VOXEL_TARGET: u32 = 15;
    RV_VOXELS: u32 = 16;
    RV_SPECULAR: u32 = 17;
    RV_GBUFFER_SPECULAR: u32 = 18;
    /// Side of the allocation pass's pixel tiles (spec 001 §4.2).
    RV_TILE: u32 = 16;
    /// Threads of the cache-lighting workgroups (one cache each).
    RV_LIGHT_GROUP: u32 = 64;
    /// Address-volume values: no cache yet, being allocated, refused (the cache buffer was full).
    RV_EMPTY: u32 = 0;
    RV_LOCKED: u32 = 0xFFFFFFFF;
    RV_REFUSED: u32 = 0xFFFFFFFE;
    /// Most cascades (cascades::MAX_CASCADES).
    RV_MAX_CASCADES: u32 = 4;
}
