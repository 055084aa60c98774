//! Binding numbers of the LightWave passes, seen only by shaders-glsl/gi/lightwave/.

crate::shared_constants! {
    // ---- the rig: VPLs generated from the lights ----
    VPLS_LIGHTS: u32 = 0;
    VPLS_OUT: u32 = 1;

    // ---- the gather, indirect shadows and the composite, per pixel ----
    GATHER_GBUFFER_POSITION: u32 = 0;
    GATHER_GBUFFER_NORMAL: u32 = 1;
    GATHER_GBUFFER_ALBEDO: u32 = 2;
    GATHER_VPLS: u32 = 3;
    GATHER_LIGHTS: u32 = 4;
    GATHER_SCENE_SHADOW_MAP: u32 = 5;
    GATHER_SCENE_SHADOW_VIEWS: u32 = 6;
    GATHER_VPL_SHADOW_MAP: u32 = 7;
    GATHER_VPL_SHADOW_VIEWS: u32 = 8;
    GATHER_HDR: u32 = 9;
    // the per-vertex gather's interpolation only
    GATHER_VERTICES: u32 = 10;
    GATHER_TRIANGLES: u32 = 11;
    GATHER_VERTEX_NORMALS: u32 = 12;
    GATHER_VERTEX_VALUES: u32 = 13;
    GATHER_TRIANGLE_IDS: u32 = 14;

    // ---- the per-vertex gather ----
    VERTEX_GATHER_VERTICES: u32 = 0;
    VERTEX_GATHER_NORMALS: u32 = 1;
    VERTEX_GATHER_VPLS: u32 = 2;
    VERTEX_GATHER_OUT: u32 = 3;

    // ---- composites (GATHER push constant) ----
    COMPOSITE_EQ_4_9: u32 = 0;
    COMPOSITE_SHIPPED: u32 = 1;
    COMPOSITE_DIRECT_ONLY: u32 = 2;
    COMPOSITE_FAKE: u32 = 3;

    // ---- indirect-shadow modes ----
    SHADOWS_NONE: u32 = 0;
    SHADOWS_ACCURATE: u32 = 1;
    SHADOWS_INTEGRATED: u32 = 2;
}
