#version 460
// Cache allocation (spec 001 §4.2): one thread per pixel in 16x16 tiles. Each pixel finds its
// cell (and, near a decision box's face, its cell in the next cascade); a pixel whose tile
// neighbour to the left, above or above-left has the same cell leaves it to that neighbour, so
// a chain of equal cells ends at one pixel that allocates. Allocating a cell gives each of its 8
// corners a cache unless one owns it already (compare-and-swap on the address volume); a full
// cache buffer refuses the corner, which is marked and counted, never half-written.
#include "gi/radiance_volumes/rv.glsl"
#include "gi/radiance_volumes/state.glsl"

layout(local_size_x = RV_TILE, local_size_y = RV_TILE) in;

layout(binding = RV_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = RV_ADDRESS, std430) buffer Address { uint address[]; };
layout(binding = RV_CACHES, std430) writeonly buffer Caches { vec4 caches[]; };
layout(binding = RV_STATE, std430) buffer State { RvState state; };

layout(push_constant) uniform Push {
    vec4 eye_side;      // the cascades' centre, the first cascade's side
    uvec2 size;
    uint cascade_count;
    uint resolution;
    float transition;
    uint capacity;
    uint stride;        // vec4s per cache: its position, then its SH coefficients
} pc;

RvGrid grid() {
    return RvGrid(pc.eye_side.xyz, pc.eye_side.w, pc.cascade_count, pc.resolution, pc.transition);
}

shared uint cells[2][RV_TILE][RV_TILE];

void allocate_cell(uint cell) {
    uint n = pc.resolution;
    uint per_cascade = n * n * n;
    uint i = cell / per_cascade;
    uint r = cell % per_cascade;
    uvec3 g = uvec3(r % n, (r / n) % n, r / (n * n));
    Cascade c = rv_cascade(grid(), i);
    for (uint k = 0u; k < 8u; ++k) {
        uvec3 corner = g + uvec3(k & 1u, (k >> 1) & 1u, k >> 2);
        uint slot = rv_corner_index(i, corner, n);
        if (atomicCompSwap(address[slot], RV_EMPTY, RV_LOCKED) != RV_EMPTY) continue;
        uint index = atomicAdd(state.requested, 1u);
        if (index >= pc.capacity) {
            atomicAdd(state.refused, 1u);
            atomicExchange(address[slot], RV_REFUSED);
            continue;
        }
        caches[index * pc.stride] = vec4(c.lo + vec3(corner) * c.cell, float(i));
        atomicExchange(address[slot], index + 1u);
    }
}

// Whether the cell of `layer` at (x, y) is left to an earlier pixel of the tile.
bool left_to_neighbour(uint layer, uint x, uint y, uint cell) {
    return (x > 0u && cells[layer][y][x - 1u] == cell)
        || (y > 0u && cells[layer][y - 1u][x] == cell)
        || (x > 0u && y > 0u && cells[layer][y - 1u][x - 1u] == cell);
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint x = gl_LocalInvocationID.x;
    uint y = gl_LocalInvocationID.y;
    uint own = RV_NONE;
    uint next = RV_NONE;
    if (all(lessThan(pixel, pc.size))) {
        vec4 position = imageLoad(gbuffer_position, ivec2(pixel));
        float blend;
        uint i = position.w != 0.0 ? rv_select(grid(), position.xyz, blend) : RV_NONE;
        if (i != RV_NONE) {
            uint n = pc.resolution;
            uvec3 g;
            vec3 f;
            rv_cell(grid(), i, position.xyz, g, f);
            own = i * n * n * n + g.x + n * (g.y + n * g.z);
            if (blend > 0.0) {
                rv_cell(grid(), i + 1u, position.xyz, g, f);
                next = (i + 1u) * n * n * n + g.x + n * (g.y + n * g.z);
            }
        }
    }
    cells[0][y][x] = own;
    cells[1][y][x] = next;
    barrier();
    if (own != RV_NONE && !left_to_neighbour(0u, x, y, own)) allocate_cell(own);
    if (next != RV_NONE && !left_to_neighbour(1u, x, y, next)) allocate_cell(next);
}
