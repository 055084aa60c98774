#ifndef VKGI_RV_STATE_GLSL
#define VKGI_RV_STATE_GLSL
// The counters (src/gi/radiance_volumes/passes.rs `RvState`); the first three are the lighting
// pass's indirect dispatch.
struct RvState {
    uint groups_x;
    uint groups_y;
    uint groups_z;
    uint requested;   // corners that asked for a cache this frame
    uint refused;     // of those, refused because the cache buffer was full
    uint missing;     // corners the apply pass found unallocated (the allocation invariant: 0)
    uint beyond;      // lit pixels beyond the last cascade (no cached light)
    uint pad;
};

#endif
