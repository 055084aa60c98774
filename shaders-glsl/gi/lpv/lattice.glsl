#ifndef VKGI_LATTICE_GLSL
#define VKGI_LATTICE_GLSL
// Cell (x, y, z) of a lattice with `dims` cells lives at (z * ny + y) * nx + x (rows, x
// fastest: GPUs) or, with CELLS_IN_COLUMNS, at (y * nx + x) * nz + z (columns, z fastest: CPU
// devices, whose column kernels then walk consecutive lines). lattice.rs's CellOrder.
layout(constant_id = CELLS_IN_COLUMNS_CONSTANT) const uint CELLS_IN_COLUMNS = 0u;

// How far apart neighbours along x, y and z lie in a buffer of a lattice of `dims` cells, in
// columns or in rows.
ivec3 cell_strides(ivec3 dims, bool columns) {
    return columns ? ivec3(dims.z, dims.x * dims.z, 1) : ivec3(1, dims.x, dims.x * dims.y);
}

uint lattice_index(ivec3 c, ivec3 dims) {
    ivec3 s = cell_strides(dims, CELLS_IN_COLUMNS != 0u);
    return uint(c.x * s.x + c.y * s.y + c.z * s.z);
}

bool lattice_inside(ivec3 c, ivec3 dims) {
    return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, dims));
}

#endif
