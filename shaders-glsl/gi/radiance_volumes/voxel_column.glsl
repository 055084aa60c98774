#ifndef VKGI_RV_VOXEL_COLUMN_GLSL
#define VKGI_RV_VOXEL_COLUMN_GLSL
// One triangle of the binary voxelisation (spec 001 §4.6), shared by the compute voxelisation
// (voxelize.comp) and the conservative-raster one (voxelize_raster.*): the triangle seen along
// its dominant axis w, and the voxels it marks in one column (i, j) of the other two axes u, v.
// Mirrors voxels.rs `voxelize_triangle`.

struct VoxelTriangle {
    uint u;           // the axes of the projection plane
    uint v;
    uint w;           // the dominant axis of the triangle's normal (depth)
    vec2 p[3];        // the corners in the plane (voxel units)
    vec3 edges[3];    // inward edge lines in the plane: dot(xy, e.xy) + e.z >= 0 inside
    float du;         // depth = c + du * u + dv * v on the triangle's plane
    float dv;
    float c;
    float dmin;       // the triangle's depth range
    float dmax;
};

// The triangle with corners `corner` (voxel units); false for a degenerate one.
bool voxel_triangle(vec3 corner[3], out VoxelTriangle t) {
    vec3 normal = cross(corner[1] - corner[0], corner[2] - corner[0]);
    vec3 a = abs(normal);
    if (max(a.x, max(a.y, a.z)) == 0.0) return false;
    t.w = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
    t.u = (t.w + 1u) % 3u;
    t.v = (t.w + 2u) % 3u;
    float depth[3];
    for (uint i = 0u; i < 3u; ++i) {
        t.p[i] = vec2(corner[i][t.u], corner[i][t.v]);
        depth[i] = corner[i][t.w];
    }
    vec2 p0 = t.p[0];
    vec2 p1 = t.p[1];
    vec2 p2 = t.p[2];
    float orientation = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
    float sign_ = orientation >= 0.0 ? 1.0 : -1.0;
    for (uint e = 0u; e < 3u; ++e) {
        vec2 s = t.p[e];
        vec2 q = t.p[(e + 1u) % 3u];
        vec2 en = vec2(-(q.y - s.y), q.x - s.x) * sign_;
        t.edges[e] = vec3(en, -(en.x * s.x + en.y * s.y));
    }
    t.du = -normal[t.u] / normal[t.w];
    t.dv = -normal[t.v] / normal[t.w];
    t.c = depth[0] - t.du * p0.x - t.dv * p0.y;
    t.dmin = min(depth[0], min(depth[1], depth[2]));
    t.dmax = max(depth[0], max(depth[1], depth[2]));
    return true;
}

// Whether column (i, j) lies in the triangle's bounding box, clamped to the cube (the
// separating axes of the projection plane; the compute pass loops over exactly these columns).
bool voxel_column_in_box(VoxelTriangle t, uvec2 column, uint resolution) {
    float n = float(resolution);
    vec2 lo = min(t.p[0], min(t.p[1], t.p[2]));
    vec2 hi = max(t.p[0], max(t.p[1], t.p[2]));
    vec2 first = floor(max(lo, vec2(0.0)));
    vec2 last = floor(min(hi, vec2(n - 1.0)));
    vec2 at = vec2(column);
    return all(greaterThanEqual(at, first)) && all(lessThanEqual(at, last));
}

// Whether the square of column (i, j) overlaps the projected triangle (its edges' separating
// axes; with `voxel_column_in_box`, the exact test).
bool voxel_column_overlaps(VoxelTriangle t, uvec2 column) {
    vec2 xy = vec2(column);
    bool inside = true;
    for (uint e = 0u; e < 3u; ++e) {
        vec2 corner = xy + vec2(t.edges[e].x >= 0.0 ? 1.0 : 0.0, t.edges[e].y >= 0.0 ? 1.0 : 0.0);
        inside = inside && dot(t.edges[e].xy, corner) + t.edges[e].z >= 0.0;
    }
    return inside;
}

// The depth range [k0, k1] of the voxels the triangle's plane passes through over the square of
// column (i, j), within its depth range; false where it leaves the cube.
bool voxel_column_range(VoxelTriangle t, uvec2 column, uint resolution, out uint k0, out uint k1) {
    float n = float(resolution);
    float spread = 0.5 * (abs(t.du) + abs(t.dv));
    float centre = t.c + t.du * (float(column.x) + 0.5) + t.dv * (float(column.y) + 0.5);
    float z0 = max(centre - spread, t.dmin);
    float z1 = min(centre + spread, t.dmax);
    if (z1 < 0.0 || z0 >= n) return false;
    k0 = uint(max(floor(z0), 0.0));
    k1 = uint(min(floor(z1), n - 1.0));
    return true;
}

// The index of the voxel at (column, k) in a cube of `side`.
uint voxel_column_index(VoxelTriangle t, uvec2 column, uint k, uint side) {
    uvec3 voxel;
    voxel[t.u] = column.x;
    voxel[t.v] = column.y;
    voxel[t.w] = k;
    return voxel.x + side * (voxel.y + side * voxel.z);
}

#endif
