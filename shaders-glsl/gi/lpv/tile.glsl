#ifndef VKGI_LPV_TILE_GLSL
#define VKGI_LPV_TILE_GLSL
// How a propagation step walks its cells and reads their sources. The including shader defines
// LPV_TILED and LPV_COLUMN (one of them 1, or neither for the naive kernel), COLUMN_FACES_ONLY
// (1 when the step reads only face neighbours) and what cells.glsl asks for, and a
// push-constant block `pc` with `ivec4 dims`; step_main.glsl walks the cells (tiled:
// prepare_sources() first, in uniform control flow; column: load_plane() or load_cells() along
// the column, and for the block advance_column()). Each reader gives source_light(cell, offset,
// channel) and source_geometry(cell, offset).
//
// Tiled: the workgroup (one tile of cells) loads its cells plus a one-cell halo of light and
// geometry into shared memory, zero outside the lattice. Shared memory is laid out [x][y][z]
// with z innermost and padded by Z_PAD cells: neighbouring threads differ in x, so the pad makes
// their stride odd and spreads them over the banks (the thesis's CUDA kernel: padding z, and
// only z, removed the bank conflicts).
#ifndef COLUMN_STREAM
#define COLUMN_STREAM 0
#endif
#ifndef COLUMN_SHARED_ROWS
#define COLUMN_SHARED_ROWS 0
#endif
#if LPV_COLUMN && !COLUMN_STREAM && !COLUMN_FACES_ONLY
#error "the column block keeps only its own columns off the current plane: face neighbours only"
#endif
#include "gi/lpv/lattice.glsl"
#include "gi/lpv/cells.glsl"

#if LPV_TILED
layout(constant_id = 3) const uint Z_PAD = 1u;
const uint TILE_X = gl_WorkGroupSize.x + 2u;
const uint TILE_Y = gl_WorkGroupSize.y + 2u;
const uint TILE_Z = gl_WorkGroupSize.z + 2u;
const uint TILE_CELLS = TILE_X * TILE_Y * TILE_Z;
shared vec4 tile_light[TILE_X * TILE_Y * (TILE_Z + Z_PAD) * CHANNELS];
shared vec4 tile_geometry[TILE_X * TILE_Y * (TILE_Z + Z_PAD) * GEOMETRY_WORDS];

uint tile_index(ivec3 t) {
    return (uint(t.x) * TILE_Y + uint(t.y)) * (TILE_Z + Z_PAD) + uint(t.z);
}

void prepare_sources() {
    ivec3 origin = ivec3(gl_WorkGroupID * gl_WorkGroupSize);
    uint threads = gl_WorkGroupSize.x * gl_WorkGroupSize.y * gl_WorkGroupSize.z;
    for (uint i = gl_LocalInvocationIndex; i < TILE_CELLS; i += threads) {
        ivec3 t = ivec3(i % TILE_X, (i / TILE_X) % TILE_Y, i / (TILE_X * TILE_Y));
        ivec3 g = origin + t - 1;
        bool inside = lattice_inside(g, pc.dims.xyz);
        uint k = inside ? lattice_index(g, pc.dims.xyz) : 0u;
        [[unroll]] for (int c = 0; c < CHANNELS; ++c) {
            tile_light[tile_index(t) * CHANNELS + c] = inside ? stored_light(k, c) : vec4(0.0);
        }
        for (uint w = 0u; w < GEOMETRY_READ_WORDS; ++w) {
            tile_geometry[tile_index(t) * GEOMETRY_WORDS + w] =
                inside ? stored_geometry(k, w) : vec4(0.0);
        }
    }
    barrier();
}

vec4 source_light(ivec3 cell, ivec3 offset, int c) {
    return tile_light[tile_index(ivec3(gl_LocalInvocationID) + 1 + offset) * CHANNELS + c];
}

GeometryWords source_geometry(ivec3 cell, ivec3 offset) {
    uint t = tile_index(ivec3(gl_LocalInvocationID) + 1 + offset) * GEOMETRY_WORDS;
    GeometryWords g = no_geometry();
    for (uint w = 0u; w < GEOMETRY_READ_WORDS; ++w) g.w[w] = tile_geometry[t + w];
    return g;
}
#elif LPV_COLUMN
// Column (and shared rows, COLUMN_SHARED_ROWS below, which read a plane differently): each
// thread steps along z through COLUMN cells of a bundle of BUNDLE x BUNDLE
// neighbouring columns and loads each plane of (BUNDLE + 2)² cells around them once for the
// whole bundle (ILPV: 9 cells a column for one column, 4 for a bundle of 2x2) into registers
// (slots indexed by constant offsets once the loops are unrolled). Two walks (step_main.glsl):
// * the block (COLUMN_STREAM 0: LPV, whose step reads face neighbours only) walks up keeping
//   the bundle's own columns in the planes below, at and above it and the rest of the current
//   plane's square (without its corners), read anew for each plane; each cell of the bundle
//   gathers from it, and the own columns then move one plane (two cells copied a column);
// * the stream (COLUMN_STREAM 1: ILPV, whose gather comes in plane groups, gather_group) walks
//   down keeping one plane: each plane adds its group to the bundle's cells at z + 1, z and
//   z - 1, whose partial sums the thread carries, and nothing else is copied from plane to
//   plane. Walking down, each cell's groups add in its gather's order: the gather's bits.
layout(constant_id = 5) const uint COLUMN = 8u;
// 1 where the columns are not split, each thread's piece its whole column (COLUMN is the
// lattice's depth: src/gi/lpv/technique.rs column_cells): the planes just past a piece, below
// and above the lattice, hold no light. ILPV's stream neither reads them nor adds their terms
// (zeros, which leave a partial sum's bits as they are where subnormals are kept); LPV's block
// starts from a zero plane instead of reading the one below (the one above its last cell is
// still read, inside its loop).
layout(constant_id = 9) const uint WHOLE_COLUMNS = 0u;
layout(constant_id = 6) const int BUNDLE = 1;
const int BLOCK_SIDE = BUNDLE + 2;
const int BLOCK_PLANE = BLOCK_SIDE * BLOCK_SIDE;
const int BLOCK_PLANES = COLUMN_STREAM != 0 ? 1 : 3;
vec4 column_light[BLOCK_PLANES * BLOCK_PLANE * CHANNELS];
GeometryWords column_geometry[BLOCK_PLANES * BLOCK_PLANE];
// The bundle's column whose cell gather() or gather_group() is computing (step_main.glsl; a
// constant once its loops are unrolled).
ivec2 bundle_member;

// The slot of the cell at `offset` from the bundle's first column: in plane dz = offset.z of the
// block, in the stream's one plane whatever its z.
uint block_slot(ivec3 offset) {
    int plane = COLUMN_STREAM != 0 ? 0 : offset.z + 1;
    return uint(plane * BLOCK_PLANE + (offset.y + 1) * BLOCK_SIDE + offset.x + 1);
}

// Whether the cell at (dx, dy) from the bundle's first column is one of the bundle's own.
bool own_column(int dx, int dy) {
    return dx >= 0 && dx < BUNDLE && dy >= 0 && dy < BUNDLE;
}

// What a step reads of one cell.
struct CellWords {
    vec4 light[CHANNELS];
    GeometryWords geometry;
};

// Cell `c`'s light and geometry where `wanted` and inside the lattice, zero elsewhere.
CellWords read_cell(ivec3 c, bool wanted) {
    bool inside = wanted && lattice_inside(c, pc.dims.xyz);
    uint k = inside ? lattice_index(c, pc.dims.xyz) : 0u;
    CellWords w;
    [[unroll]] for (int ch = 0; ch < CHANNELS; ++ch) {
        w.light[ch] = inside ? stored_light(k, ch) : vec4(0.0);
    }
    w.geometry = stored_cell_geometry(k, inside);
    return w;
}

// The cell at `offset` from the column into its slot.
void put_cell(ivec3 offset, CellWords w) {
    uint slot = block_slot(offset);
    [[unroll]] for (int ch = 0; ch < CHANNELS; ++ch) column_light[slot * CHANNELS + ch] = w.light[ch];
    column_geometry[slot] = w.geometry;
}

// Of the plane z = origin.z + dz around the bundle whose first column is at `origin`, the
// bundle's own columns (`own`) and the cells around them (`around`) into their slots (zero
// outside); with COLUMN_FACES_ONLY never the square's 4 corners, which a face-neighbour step
// does not read. Slots not asked for keep what they hold.
void load_cells(ivec3 origin, int dz, bool own, bool around) {
    [[unroll]] for (int dy = -1; dy <= BUNDLE; ++dy) {
        [[unroll]] for (int dx = -1; dx <= BUNDLE; ++dx) {
            // Constants once unrolled: the cells not wanted are neither loaded nor written.
            bool corner = (dx == -1 || dx == BUNDLE) && (dy == -1 || dy == BUNDLE);
            bool asked = own_column(dx, dy) ? own : around;
            if (!asked || (COLUMN_FACES_ONLY != 0 && corner)) continue;
            ivec3 offset = ivec3(dx, dy, dz);
            put_cell(offset, read_cell(origin + offset, true));
        }
    }
}

#if COLUMN_SHARED_ROWS
// Shared rows (`--kernel shared-rows`: one column a thread, BUNDLE 1): a thread reads its own
// column's cell of each row it needs and takes the cells at x - 1 and x + 1 from the lanes
// beside it; the subgroup's two ends come from one more read, lane j reading the j-th end (the
// left end of row j / 2 where j is even, its right end where j is odd). src/gi/lpv/technique.rs
// allows the kernel where the lanes lie along x as this assumes: a CPU device, whose subgroups
// are runs of consecutive invocations, and workgroups whose width is a whole number of them.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require

// The ends of `rows` rows from dy = `first_dy` of plane dz around the column at `origin`: this
// lane's one, if any.
CellWords read_ends(ivec3 origin, int dz, int first_dy, int rows) {
    int j = int(gl_SubgroupInvocationID);
    ivec3 row_start = origin - ivec3(j, 0, 0);
    int x = (j & 1) != 0 ? int(gl_SubgroupSize) : -1;
    return read_cell(row_start + ivec3(x, first_dy + j / 2, dz), j < 2 * rows);
}

// `own` of the lane at `side` (-1 or 1) of this one, or at the subgroup's end the end `end` of
// `ends`. Both shuffles run in every lane (a lane that skipped one would leave its value
// undefined for the others).
vec4 from_lane_beside(vec4 own, vec4 ends, uint end, int side) {
    uint lane = gl_SubgroupInvocationID;
    bool at_end = side < 0 ? lane == 0u : lane == gl_SubgroupSize - 1u;
    vec4 beside = subgroupShuffle(own, at_end ? lane : uint(int(lane) + side));
    vec4 end_value = subgroupShuffle(ends, end);
    return at_end ? end_value : beside;
}

// The cell at x + `side` of the row whose cell at x is `own` (end `end` of `ends` at the
// subgroup's end), zero outside the lattice's x range (`inside` false).
CellWords cell_beside(CellWords own, CellWords ends, uint end, int side, bool inside) {
    CellWords c;
    [[unroll]] for (int ch = 0; ch < CHANNELS; ++ch) {
        vec4 v = from_lane_beside(own.light[ch], ends.light[ch], end, side);
        c.light[ch] = inside ? v : vec4(0.0);
    }
    c.geometry = no_geometry();
    for (uint w = 0u; w < GEOMETRY_READ_WORDS; ++w) {
        vec4 v = from_lane_beside(own.geometry.w[w], ends.geometry.w[w], end, side);
        c.geometry.w[w] = inside ? v : vec4(0.0);
    }
    return c;
}

// Row dy of plane dz around the column at `origin`, whose ends are `ends` from `first_dy` on:
// its cells at x - 1, x and x + 1 into their slots.
void load_row(ivec3 origin, int dz, int dy, CellWords ends, int first_dy, CellWords own) {
    uint left_end = uint(2 * (dy - first_dy));
    put_cell(ivec3(-1, dy, dz), cell_beside(own, ends, left_end, -1, origin.x > 0));
    put_cell(ivec3(1, dy, dz), cell_beside(own, ends, left_end + 1u, 1, origin.x + 1 < pc.dims.x));
}
#endif

// The whole plane dz around the bundle (the stream's).
void load_plane(ivec3 origin, int dz) {
#if COLUMN_SHARED_ROWS
    CellWords ends = read_ends(origin, dz, -1, 3);
    [[unroll]] for (int dy = -1; dy <= 1; ++dy) {
        CellWords own = read_cell(origin + ivec3(0, dy, dz), true);
        put_cell(ivec3(0, dy, dz), own);
        load_row(origin, dz, dy, ends, -1, own);
    }
#else
    load_cells(origin, dz, true, true);
#endif
}

// The block's current plane around its own columns (the block's: LPV's face neighbours).
void load_around(ivec3 origin) {
#if COLUMN_SHARED_ROWS
    // The cells at y - 1 and y + 1 read, those at x - 1 and x + 1 from the lanes beside.
    CellWords ends = read_ends(origin, 0, 0, 1);
    uint slot = block_slot(ivec3(0));
    CellWords own;
    [[unroll]] for (int ch = 0; ch < CHANNELS; ++ch) own.light[ch] = column_light[slot * CHANNELS + ch];
    own.geometry = column_geometry[slot];
    load_row(origin, 0, 0, ends, 0, own);
    put_cell(ivec3(0, -1, 0), read_cell(origin + ivec3(0, -1, 0), true));
    put_cell(ivec3(0, 1, 0), read_cell(origin + ivec3(0, 1, 0), true));
#else
    load_cells(origin, 0, false, true);
#endif
}

// The own columns' cells of the block's plane dz, zero: below a whole column.
void clear_own_columns(int dz) {
    [[unroll]] for (int dy = 0; dy < BUNDLE; ++dy) {
        [[unroll]] for (int dx = 0; dx < BUNDLE; ++dx) {
            uint slot = block_slot(ivec3(dx, dy, dz));
            [[unroll]] for (int ch = 0; ch < CHANNELS; ++ch) {
                column_light[slot * CHANNELS + ch] = vec4(0.0);
            }
            column_geometry[slot] = no_geometry();
        }
    }
}

#if COLUMN_STREAM
// The geometry of `cell` (zero outside) where the blocking reads a cell's own geometry (the
// visibility model's four words); otherwise none, and nothing is read.
GeometryWords own_geometry(ivec3 cell) {
    if (GEOMETRY_WORDS != 4u) return no_geometry();
    bool inside = lattice_inside(cell, pc.dims.xyz);
    return stored_cell_geometry(inside ? lattice_index(cell, pc.dims.xyz) : 0u, inside);
}
#else
// Move the block one cell along +z: the own columns' cells at dz = 0 and 1 become those at -1
// and 0 (the rest of the new current plane is read for it).
void advance_column() {
    [[unroll]] for (int dz = 0; dz <= 1; ++dz) {
        [[unroll]] for (int dy = 0; dy < BUNDLE; ++dy) {
            [[unroll]] for (int dx = 0; dx < BUNDLE; ++dx) {
                uint to = block_slot(ivec3(dx, dy, dz - 1));
                uint from = block_slot(ivec3(dx, dy, dz));
                [[unroll]] for (int c = 0; c < CHANNELS; ++c) {
                    column_light[to * CHANNELS + c] = column_light[from * CHANNELS + c];
                }
                column_geometry[to] = column_geometry[from];
            }
        }
    }
}
#endif

vec4 source_light(ivec3 cell, ivec3 offset, int c) {
    return column_light[block_slot(offset + ivec3(bundle_member, 0)) * CHANNELS + c];
}

GeometryWords source_geometry(ivec3 cell, ivec3 offset) {
    return column_geometry[block_slot(offset + ivec3(bundle_member, 0))];
}
#else
void prepare_sources() {}

vec4 source_light(ivec3 cell, ivec3 offset, int channel) {
    ivec3 c = cell + offset;
    return lattice_inside(c, pc.dims.xyz) ? stored_light(lattice_index(c, pc.dims.xyz), channel)
                                          : vec4(0.0);
}

GeometryWords source_geometry(ivec3 cell, ivec3 offset) {
    ivec3 c = cell + offset;
    GeometryWords g = no_geometry();
    if (lattice_inside(c, pc.dims.xyz)) {
        uint k = lattice_index(c, pc.dims.xyz);
        for (uint w = 0u; w < GEOMETRY_READ_WORDS; ++w) g.w[w] = stored_geometry(k, w);
    }
    return g;
}
#endif

#endif
