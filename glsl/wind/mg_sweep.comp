#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, one red-black Gauss-Seidel sweep on level pc.mg_level, both
// colours in one dispatch (`wind.sweep = "fused"`): the red cells, then
// the black, take the value that zeroes their residual (`Level::smooth`
// with colour 0, then 1; mg_smooth.comp runs one colour a dispatch). A GPU
// pays a dispatch's drain for every dependent dispatch: on the paper's
// grid a V-cycle was 45 of them, 16 of those half-sweeps.
//
// Each workgroup sweeps one tile (MG_SWEEP_TILE_*). It works out the red
// cells of the tile and of one cell around it from the black cells as the
// sweep found them, keeping them in shared memory, then the tile's black
// cells from those: a black cell's red neighbours all lie in the tile or
// one cell around it. The red cells around a tile are a neighbour tile's
// too, worked out again from the same values by the same arithmetic, so
// every cell takes the bits the two half-sweeps give it one after the
// other. A workgroup writes cells that another reads, so a sweep reads
// one copy and writes the other (pc.mg_sweep): 0 reads the level's
// pressure and writes the sweep scratch (the saved residual's place,
// which the residual only takes after the sweeps), 1 the reverse;
// MG_PRE_SMOOTH and MG_POST_SMOOTH are even, so a level's sweeps end in its
// pressure.
#define WIND_KERNEL_GROUP MG_SWEEP_GROUP
#include "multigrid.glsl"

// The red cells' new pressure over the tile and one cell around it, a
// row's every other cell: cell c at `red_slot(c)`.
shared float red[MG_SWEEP_FLOATS];

// The box of the red cells kept, [around_lo, around_lo + around_size).
uvec3 around_lo;
uvec3 around_size;

// i / d for the small counts of a tile (i * d < 2^20): (i + 0.5) / d lies
// at least 0.5 / d from an integer, and the float division's error (a few
// ulp of the quotient, below i / 2^21) is smaller. An integer division has
// no vector instruction on a CPU, and lavapipe runs a kernel's invocations
// as vectors.
uint quotient(uint i, uint d) {
    return uint((float(i) + 0.5) / float(d));
}

// Red cell c's place in `red`: along x the red cells of a row are every
// other cell, so (x - around_lo.x) / 2 numbers them.
uint red_slot(uvec3 c) {
    uvec3 r = c - around_lo;
    return (r.x >> 1u) + (around_size.x + 1u) / 2u * (r.y + around_size.y * r.z);
}

// The pressure the sweep reads: the level's or the scratch's
// (pc.mg_sweep).
float source_p(uint l, uint index) {
    return pc.mg_sweep != 0u ? pressure[cell_count() + index] : mg_p(l, index);
}

// The pressure the sweep writes: the other.
void set_result(uint l, uint index, float p) {
    if (pc.mg_sweep != 0u) {
        mg_set_p(l, index, p);
    } else {
        pressure[cell_count() + index] = p;
    }
}

// `mg_smoothed` at cell c with the neighbours' pressure NEIGHBOUR(side):
// the same terms summed in the same order.
#define SMOOTHED(NAME, NEIGHBOUR)                                               \
    float NAME(uint l, uvec3 c) {                                               \
        float k[6];                                                             \
        uint nb[6];                                                             \
        bool inside[6];                                                         \
        mg_stencil_terms(l, c, k, nb, inside);                                  \
        vec2 s = vec2(0.0);                                                     \
        for (uint axis = 0u; axis < 3u; ++axis) {                               \
            s.x += k[2u * axis] + k[2u * axis + 1u];                            \
            for (uint side = 2u * axis; side < 2u * axis + 2u; ++side) {        \
                if (inside[side]) {                                             \
                    s.y += k[side] * NEIGHBOUR(side);                           \
                }                                                               \
            }                                                                   \
        }                                                                       \
        return s.x == 0.0 ? 0.0 : (mg_b(l, mg_cell_index(l, c)) + s.y) / s.x; \
    }

const uvec3 STEPS[6] = uvec3[6](uvec3(-1, 0, 0), uvec3(1, 0, 0), uvec3(0, -1, 0),
                                uvec3(0, 1, 0), uvec3(0, 0, -1), uvec3(0, 0, 1));
// A red cell's neighbours are black, as the sweep found them (the source,
// which no workgroup writes); a black cell's are red, swept (`red`).
#define FOUND(side) source_p(l, nb[side])
#define SWEPT(side) red[red_slot(c + STEPS[side])]
SMOOTHED(red_smoothed, FOUND)
SMOOTHED(black_smoothed, SWEPT)

// Slots for one colour's cells in a box of `size`: every other cell of a
// row, rounded up (`mg_color_cell_count`'s count for a level).
uint color_slots(uvec3 size) {
    return (size.x + 1u) / 2u * size.y * size.z;
}

// The cells of colour `color` in the box [lo, lo + size), counted as
// `mg_cell_of_color` counts a level's (every other cell along x), each
// cell number i: false where i is its row's one too many.
bool color_cell(uvec3 lo, uvec3 size, uint color, uint i, out uvec3 c) {
    uint half_x = (size.x + 1u) / 2u;
    uint row = quotient(i, half_x);
    uint z = quotient(row, size.y);
    c.y = lo.y + row - z * size.y;
    c.z = lo.z + z;
    c.x = lo.x + 2u * (i - row * half_x) + ((lo.x + c.y + c.z + color) & 1u);
    return c.x < lo.x + size.x;
}

void main() {
    uint l = mg_level();
    uvec3 n = levels[l].cells;
    uvec3 tile = min(n, uvec3(MG_SWEEP_TILE_X, MG_SWEEP_TILE_Y, MG_SWEEP_TILE_Z));
    uvec3 tiles = (n + tile - 1u) / tile;
    uint g = gl_WorkGroupID.x;
    uvec3 lo = uvec3(g % tiles.x, (g / tiles.x) % tiles.y, g / (tiles.x * tiles.y)) * tile;
    uvec3 hi = min(lo + tile, n);
    around_lo = uvec3(max(ivec3(lo) - 1, ivec3(0)));
    around_size = min(hi + 1u, n) - around_lo;
    // The red cells of the tile and around it, from the black cells as
    // the sweep found them (the source, which no workgroup writes).
    uvec3 c;
    uint reds = color_slots(around_size);
    for (uint i = gl_LocalInvocationID.x; i < reds; i += MG_SWEEP_GROUP) {
        if (!color_cell(around_lo, around_size, 0u, i, c)) {
            continue;
        }
        float p = red_smoothed(l, c);
        red[red_slot(c)] = p;
        if (all(greaterThanEqual(c, lo)) && all(lessThan(c, hi))) {
            set_result(l, mg_cell_index(l, c), p);
        }
    }
    barrier();
    // The black cells of the tile, from the red cells swept.
    uvec3 size = hi - lo;
    uint blacks = color_slots(size);
    for (uint i = gl_LocalInvocationID.x; i < blacks; i += MG_SWEEP_GROUP) {
        if (color_cell(lo, size, 1u, i, c)) {
            set_result(l, mg_cell_index(l, c), black_smoothed(l, c));
        }
    }
}
