#ifndef VKGI_LPV_TILE_GLSL
#define VKGI_LPV_TILE_GLSL
// Where a propagation step reads its source cells. The including shader defines LPV_TILED,
// declares the buffers `source_cells` and `geometry_cells` (vec4 per cell) and a push-constant
// block `pc` with `ivec4 dims`, and calls prepare_sources() in uniform control flow first.
//
// Tiled: the workgroup (one tile of cells) loads its cells plus a one-cell halo of light and
// geometry into shared memory, zero outside the lattice. Shared memory is laid out [x][y][z]
// with z innermost and padded by Z_PAD cells: neighbouring threads differ in x, so the pad makes
// their stride odd and spreads them over the banks (the thesis's CUDA kernel: padding z, and
// only z, removed the bank conflicts).
#include "gi/lpv/lattice.glsl"

#if LPV_TILED
layout(constant_id = 3) const uint Z_PAD = 1u;
const uint TILE_X = gl_WorkGroupSize.x + 2u;
const uint TILE_Y = gl_WorkGroupSize.y + 2u;
const uint TILE_Z = gl_WorkGroupSize.z + 2u;
const uint TILE_CELLS = TILE_X * TILE_Y * TILE_Z;
shared vec4 tile_light[TILE_X * TILE_Y * (TILE_Z + Z_PAD)];
shared vec4 tile_geometry[TILE_X * TILE_Y * (TILE_Z + Z_PAD)];

uint tile_index(ivec3 t) {
    return (uint(t.x) * TILE_Y + uint(t.y)) * (TILE_Z + Z_PAD) + uint(t.z);
}

void prepare_sources() {
    ivec3 origin = ivec3(gl_WorkGroupID * gl_WorkGroupSize);
    uint threads = gl_WorkGroupSize.x * gl_WorkGroupSize.y * gl_WorkGroupSize.z;
    for (uint i = gl_LocalInvocationIndex; i < TILE_CELLS; i += threads) {
        ivec3 t = ivec3(i % TILE_X, (i / TILE_X) % TILE_Y, i / (TILE_X * TILE_Y));
        ivec3 g = origin + t - 1;
        vec4 light = vec4(0.0);
        vec4 geometry = vec4(0.0);
        if (lattice_inside(g, pc.dims.xyz)) {
            uint k = lattice_index(g, pc.dims.xyz);
            light = source_cells[k];
            geometry = geometry_cells[k];
        }
        tile_light[tile_index(t)] = light;
        tile_geometry[tile_index(t)] = geometry;
    }
    barrier();
}

vec4 source_light(ivec3 cell, ivec3 offset) {
    return tile_light[tile_index(ivec3(gl_LocalInvocationID) + 1 + offset)];
}

vec4 source_geometry(ivec3 cell, ivec3 offset) {
    return tile_geometry[tile_index(ivec3(gl_LocalInvocationID) + 1 + offset)];
}
#else
void prepare_sources() {}

vec4 source_light(ivec3 cell, ivec3 offset) {
    ivec3 c = cell + offset;
    return lattice_inside(c, pc.dims.xyz) ? source_cells[lattice_index(c, pc.dims.xyz)] : vec4(0.0);
}

vec4 source_geometry(ivec3 cell, ivec3 offset) {
    ivec3 c = cell + offset;
    return lattice_inside(c, pc.dims.xyz) ? geometry_cells[lattice_index(c, pc.dims.xyz)] : vec4(0.0);
}
#endif

#endif
