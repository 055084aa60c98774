//! Constants shared by Rust and GLSL that every shader sees: the frame's own binding numbers,
//! workgroup sizes and limits live here and nowhere else. build.rs hands each one to shaderc as
//! a `#define` of the same name, so a shader writes `layout(binding = LIGHTING_GBUFFER_POSITION)`
//! and Rust binds `LIGHTING_GBUFFER_POSITION`. GI methods declare theirs in their own folder
//! (src/gi/<name>/bindings.rs, seen only by shaders-glsl/gi/<name>/; src/gi/shared/bindings.rs,
//! seen by every GI shader) with the same macro.

/// Declare constants shared with GLSL, one `NAME: TYPE = LITERAL;` per line (build.rs reads
/// these lines to define the same names for the shaders).
#[macro_export]
macro_rules! shared_constants {
    ($($(#[$doc:meta])* $name:ident: $ty:ty = $value:literal;)*) => {
        $($(#[$doc])* pub const $name: $ty = $value;)*
    };
}

shared_constants! {
    // ---- scene buffers, bound by every pass that reads geometry ----
    /// Workgroup edge of 2D image passes (lighting, tone mapping): 8x8 threads.
    IMAGE_WORKGROUP: u32 = 8;
    /// Workgroup size of 1D passes.
    LINEAR_WORKGROUP: u32 = 64;

    /// Specialisation constant of every shader that includes common/texture.glsl: 0 when no
    /// material of the scene has an albedo texture, so the texture code is compiled out
    /// (lavapipe runs both sides of a branch, so a per-pixel test would not skip it).
    SPEC_SCENE_TEXTURED: u32 = 31;

    // ---- shadow and G-buffer rasterisation (vertex pulling) ----
    RASTER_VERTICES: u32 = 0;
    RASTER_TRIANGLES: u32 = 1;
    RASTER_MATERIALS: u32 = 2;
    RASTER_TEXTURES: u32 = 3;

    // ---- deferred direct lighting ----
    /// Flat varyings (vec4 words) that carry the shared lights and their shadow views from
    /// raster/lighting.vert to raster/lighting.frag: 4 words a light, 5 a view. 15 words (60
    /// components) fit every Vulkan device's vertex outputs and fragment inputs (at least 64).
    LIGHTING_VARYING_WORDS: u32 = 15;
    /// Words of one light among those varyings (raster/light_words.glsl).
    LIGHTING_LIGHT_WORDS: u32 = 4;
    /// Words of one shadow view: the view-projection's columns and the parameters.
    LIGHTING_VIEW_WORDS: u32 = 5;
    LIGHTING_GBUFFER_POSITION: u32 = 0;
    LIGHTING_GBUFFER_NORMAL: u32 = 1;
    LIGHTING_GBUFFER_ALBEDO: u32 = 2;
    LIGHTING_GBUFFER_EMISSION: u32 = 3;
    LIGHTING_SHADOW_MAP: u32 = 4;
    LIGHTING_LIGHTS: u32 = 5;
    LIGHTING_SHADOW_VIEWS: u32 = 6;
    LIGHTING_HDR_OUT: u32 = 7;
    LIGHTING_GBUFFER_SPECULAR: u32 = 8;

    // ---- window overlay ----
    OVERLAY_TARGET: u32 = 0;
    OVERLAY_MASK: u32 = 1;
    /// Overlay mask values: leave the pixel, darken it (text box), draw text.
    OVERLAY_CLEAR: u32 = 0;
    OVERLAY_BOX: u32 = 1;
    OVERLAY_TEXT: u32 = 2;

    // ---- red-cyan anaglyph of a stereo pair (CAVE nodes) ----
    ANAGLYPH_LEFT: u32 = 0;
    ANAGLYPH_RIGHT: u32 = 1;
    ANAGLYPH_TARGET: u32 = 2;

    // ---- tone mapping ----
    TONEMAP_HDR_IN: u32 = 0;
    // The compute form's output: the 8-bit image's UNORM view (raster/tonemap.comp).
    TONEMAP_LDR_OUT: u32 = 1;

    // ---- reference path tracer ----
    REFERENCE_VERTICES: u32 = 0;
    REFERENCE_TRIANGLES: u32 = 1;
    REFERENCE_MATERIALS: u32 = 2;
    REFERENCE_LIGHTS: u32 = 3;
    REFERENCE_BVH_NODES: u32 = 4;
    REFERENCE_BVH_TRIANGLES: u32 = 5;
    REFERENCE_DIRECT_SUM: u32 = 6;
    REFERENCE_INDIRECT_SUM: u32 = 7;
    REFERENCE_EMITTERS: u32 = 8;
    REFERENCE_TEXTURES: u32 = 9;
    /// First random-number dimension of the emitter samples (three per path vertex), apart
    /// from the bounce dimensions 2 + 3 * depth.
    REFERENCE_EMITTER_DIM: u32 = 65536;
    /// Which strategies light a surface from emitters: both with multiple importance sampling,
    /// emitter sampling (next-event estimation) alone, or BSDF-sampled hits alone.
    REFERENCE_STRATEGY_MIS: u32 = 0;
    REFERENCE_STRATEGY_LIGHT: u32 = 1;
    REFERENCE_STRATEGY_BSDF: u32 = 2;
    /// `max_bounces` value meaning "no limit" (paths end by Russian roulette).
    REFERENCE_UNLIMITED_BOUNCES: u32 = 0xFFFFFFFF;
    /// Hard cap on path length, even without a bounce limit.
    REFERENCE_MAX_DEPTH: u32 = 1024;

    // ---- device-limit probes ----
    LIMITS_SOURCE: u32 = 0;
    LIMITS_DESTINATION: u32 = 1;
    /// FMAs of each chain per trip of the probe's loop (unrolled).
    LIMITS_FMA_UNROLL: u32 = 32;

    // ---- lights ----
    LIGHT_KIND_SPOT: u32 = 0;
    LIGHT_KIND_POINT: u32 = 1;
    LIGHT_KIND_COSINE: u32 = 2;
    /// Shadow-map texels a PCF footprint spans on each side of its centre.
    SHADOW_PCF_RADIUS: i32 = 1;
}
