//! Binding numbers of the irradiance-cache passes, seen only by shaders-glsl/gi/irradiance_cache/.
//! A resource has the same number in every pass that binds it.

crate::shared_constants! {
    IC_RECORDS: u32 = 0;
    IC_STATE: u32 = 1;
    IC_CANDIDATES: u32 = 2;
    IC_GBUFFER_POSITION: u32 = 3;
    IC_GBUFFER_NORMAL: u32 = 4;
    IC_GBUFFER_ALBEDO: u32 = 5;
    IC_SPLAT: u32 = 6;
    IC_HEMISPHERE: u32 = 7;
    IC_TABLES: u32 = 8;
    IC_HDR: u32 = 9;
    IC_VERTICES: u32 = 10;
    IC_TRIANGLES: u32 = 11;
    IC_MATERIALS: u32 = 12;
    IC_TEXTURES: u32 = 13;
    IC_LIGHTS: u32 = 14;
    IC_SHADOW_VIEWS: u32 = 15;
    IC_SHADOW_MAP: u32 = 16;
    IC_PREVIOUS: u32 = 17;
    IC_DRAWS: u32 = 18;
    /// Threads of the hemisphere-reduction and snapshot workgroups.
    IC_WORKGROUP: u32 = 256;
    /// Threads of the tile-selection workgroups: the smallest tile (8x8 pixels) gets a thread
    /// a pixel (at 256 it had four, and two more barriers; 3-4x slower on lavapipe).
    IC_SELECT_WORKGROUP: u32 = 64;
    /// No candidate in a tile.
    IC_NONE: u32 = 0xFFFFFFFF;
    /// Smallest inverse weight (spec 003 Alg. 3 EPSILON; cpu::MIN_INVERSE_WEIGHT).
    IC_MIN_INVERSE_WEIGHT: f32 = 1e-4;
    /// Ward's "in front" tolerance as a fraction of R (cpu::BEHIND_TOLERANCE).
    IC_BEHIND_TOLERANCE: f32 = 0.05;
    /// Most bounces a cache computes (`--bounces inf` stops here if not converged before).
    IC_MAX_BOUNCES: u32 = 32;
    /// `--bounces inf` stops when Σ E over the records changed by less than this fraction.
    IC_BOUNCE_TOLERANCE: f32 = 1e-3;
    /// Largest weight a record gives a point.
    IC_MAX_WEIGHT: f32 = 1e4;
    /// Smallest clip w of a splat box's corner (cpu::MIN_CLIP_W).
    IC_MIN_CLIP_W: f32 = 1e-6;
}
