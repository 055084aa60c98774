#ifndef VKGI_LATTICE_GLSL
#define VKGI_LATTICE_GLSL
// Cell (x, y, z) of a lattice with `dims` cells lives at (z * ny + y) * nx + x (lattice.rs).

uint lattice_index(ivec3 c, ivec3 dims) {
    return uint((c.z * dims.y + c.y) * dims.x + c.x);
}

bool lattice_inside(ivec3 c, ivec3 dims) {
    return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, dims));
}

#endif
