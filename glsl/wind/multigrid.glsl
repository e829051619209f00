// What the multigrid kernels share (mirrors src/model/multigrid.rs): the
// level table, the pressure and right-hand side of every level, the
// 6-point stencil and the interpolation weights.
#ifndef MEADOW_MULTIGRID_GLSL
#define MEADOW_MULTIGRID_GLSL

#include "wind_kernel.glsl"

// MgLevel: src/interface/defs.rs.
layout(set = 0, binding = 6, std430) readonly buffer Conductance { float conductance[]; };
// Coarse levels (1 and up): pressure at [0, C), right-hand side at [C, 2C),
// C = pc.coarse_cells.
layout(set = 0, binding = 7, std430) buffer Coarse { float coarse[]; };
layout(set = 0, binding = 8, std430) readonly buffer Levels { MgLevel levels[]; };

// Where the computations below read the level table, the face
// conductances, a level's pressure and right-hand side and the saved
// residual: the buffers by default; mg_tail.glsl defines these before
// including this file to read its workgroup's shared copies instead.
#ifndef MG_LEVELS
#define MG_LEVELS levels
#endif
#ifndef MG_CONDUCTANCE
#define MG_CONDUCTANCE(index) conductance[index]
#endif
#ifndef MG_P
#define MG_P(l, index) mg_p(l, index)
#endif
#ifndef MG_B
#define MG_B(l, index) mg_b(l, index)
#endif
#ifndef MG_SAVED_RESIDUAL
#define MG_SAVED_RESIDUAL(index) mg_saved_residual(index)
#endif

uint mg_cell_count(uint l) {
    uvec3 n = MG_LEVELS[l].cells;
    return n.x * n.y * n.z;
}

uvec3 mg_cell_of(uint l, uint index) {
    uvec3 n = MG_LEVELS[l].cells;
    return uvec3(index % n.x, (index / n.x) % n.y, index / (n.x * n.y));
}

uint mg_cell_index(uint l, uvec3 c) {
    uvec3 n = MG_LEVELS[l].cells;
    return c.x + n.x * (c.y + n.y * c.z);
}

float mg_conductance(uint l, uint axis, uvec3 f) {
    uvec3 d = MG_LEVELS[l].cells;
    d[axis] += 1u;
    return MG_CONDUCTANCE(MG_LEVELS[l].conductance[axis] + f.x + d.x * (f.y + d.y * f.z));
}

// Which levels a kernel runs on (`WindPass::level_kernel`): by default
// (MG_ANY_LEVEL 1, MG_ON_FINEST 0) any, the level the push constants
// name; or a pipeline made for level 0 (1, 1) or for the coarse levels
// (0, 0), which leaves the other kind's reads out. That matters on
// lavapipe, which runs both sides of every test: each stencil read of a
// smoothing sweep was a read of both buffers there. The constant ids lie
// past the kernels' own.
layout(constant_id = 8) const uint MG_ANY_LEVEL = 1u;
layout(constant_id = 9) const uint MG_ON_FINEST = 0u;

// The level the kernel runs on (it reads the next one too).
uint mg_level() {
    return pc.mg_level - pc.mg_level * MG_ON_FINEST;
}

bool mg_finest(uint l) {
    return ((l == 0u) ? 1u : 0u) * MG_ANY_LEVEL != 0u;
}

// Level 0's pressure is the solver's (copy 0); its right-hand side is the
// divergence integrated over the cell, negated.
float mg_p(uint l, uint index) {
    return mg_finest(l) ? pressure[index] : coarse[MG_LEVELS[l].coarse_offset + index];
}

void mg_set_p(uint l, uint index, float value) {
    if (mg_finest(l)) {
        pressure[index] = value;
    } else {
        coarse[MG_LEVELS[l].coarse_offset + index] = value;
    }
}

float mg_b(uint l, uint index) {
    if (mg_finest(l)) {
        vec3 h = pc.grid.cell_size.xyz;
        return -divergence[index] * h.x * h.y * h.z;
    }
    return coarse[pc.coarse_cells + MG_LEVELS[l].coarse_offset + index];
}

// The 6-point stencil's terms at cell c, low then high face of x, y and
// z: each face's conductance K and the neighbour's index, and whether
// the neighbour is inside the grid (beyond an open side p_nb = 0).
// Written out face by face: the face arrays are laid out like the cells
// with one more along their axis, so both faces of an axis are one stride
// apart. A wall's K is 0, so it adds nothing.
void mg_stencil_terms(uint l, uvec3 c, out float k[6], out uint nb[6], out bool inside[6]) {
    uvec3 n = MG_LEVELS[l].cells;
    uvec3 offset = MG_LEVELS[l].conductance;
    uint index = mg_cell_index(l, c);
    uint plane = n.x * n.y;
    uint fx = offset.x + c.x + (n.x + 1u) * (c.y + n.y * c.z);
    uint fy = offset.y + c.x + n.x * (c.y + (n.y + 1u) * c.z);
    uint fz = offset.z + index;
    k[0] = MG_CONDUCTANCE(fx);
    k[1] = MG_CONDUCTANCE(fx + 1u);
    k[2] = MG_CONDUCTANCE(fy);
    k[3] = MG_CONDUCTANCE(fy + n.x);
    k[4] = MG_CONDUCTANCE(fz);
    k[5] = MG_CONDUCTANCE(fz + plane);
    nb[0] = index - 1u;
    nb[1] = index + 1u;
    nb[2] = index - n.x;
    nb[3] = index + n.x;
    nb[4] = index - plane;
    nb[5] = index + plane;
    inside[0] = c.x > 0u;
    inside[1] = c.x + 1u < n.x;
    inside[2] = c.y > 0u;
    inside[3] = c.y + 1u < n.y;
    inside[4] = c.z > 0u;
    inside[5] = c.z + 1u < n.z;
}

// The 6-point stencil at cell c: x = sum of K, y = sum of K * p_nb.
vec2 mg_stencil(uint l, uvec3 c) {
    float k[6];
    uint nb[6];
    bool inside[6];
    mg_stencil_terms(l, c, k, nb, inside);
    vec2 s = vec2(0.0);
    for (uint axis = 0u; axis < 3u; ++axis) {
        s.x += k[2u * axis] + k[2u * axis + 1u];
        s.y += inside[2u * axis] ? k[2u * axis] * MG_P(l, nb[2u * axis]) : 0.0;
        s.y += inside[2u * axis + 1u] ? k[2u * axis + 1u] * MG_P(l, nb[2u * axis + 1u]) : 0.0;
    }
    return s;
}

float mg_residual(uint l, uint index) {
    vec2 s = mg_stencil(l, mg_cell_of(l, index));
    return MG_B(l, index) - (s.x * MG_P(l, index) - s.y);
}

// The value that zeroes cell c's residual: a Gauss-Seidel update
// (`Level::smooth`).
float mg_smoothed(uint l, uvec3 c) {
    vec2 s = mg_stencil(l, c);
    return s.x == 0.0 ? 0.0 : (MG_B(l, mg_cell_index(l, c)) + s.y) / s.x;
}

// Cells of one colour on level l, counted as the smoother's threads are.
uint mg_color_cell_count(uint l) {
    uvec3 n = MG_LEVELS[l].cells;
    return (n.x + 1u) / 2u * n.y * n.z;
}

// Level l's residual, written by mg_residual.comp before a restriction:
// the second half of the pressure buffer, which only the Jacobi solver's
// ping-pong uses otherwise.
float mg_saved_residual(uint index) {
    return pressure[cell_count() + index];
}

void mg_save_residual(uint index, float value) {
    pressure[cell_count() + index] = value;
}

// Cell of colour `color` number `i` of level l (x fastest, every other
// cell along x), or false past the end: the smoother's threads run only
// the colour being updated.
bool mg_cell_of_color(uint l, uint i, uint color, out uvec3 c) {
    uvec3 n = MG_LEVELS[l].cells;
    uint half_x = (n.x + 1u) / 2u;
    uint row = i / half_x;
    c.y = row % n.y;
    c.z = row / n.y;
    c.x = 2u * (i % half_x) + ((c.y + c.z + color) & 1u);
    return c.z < n.z && c.x < n.x;
}

// Centre and width of coarse cell c along one axis, in fine cells.
vec2 coarse_span(uint c, uint ratio, uint fine_count) {
    uint start = c * ratio;
    uint end = min(start + ratio, fine_count);
    return vec2(float(start + end) * 0.5, float(end - start));
}

// Fine cell f's (level l) interpolation along axis a: the coarse cells it
// reads (its parent, then the parent's neighbour on f's side, or the
// parent again where there is none) and their weights; `axis_weight` in
// src/model/multigrid.rs. Beyond the grid, an open side (its coarse face
// conducts) interpolates towards zero at one parent width; a closed side
// mirrors the parent.
void mg_axis_pair(uint l, uvec3 f, uvec3 parent, uint a, out uvec2 cells, out vec2 weights) {
    uint ratio = MG_LEVELS[l].ratio[a];
    uint fine_count = MG_LEVELS[l].cells[a];
    uint coarse_count = MG_LEVELS[l + 1u].cells[a];
    float x = float(f[a]) + 0.5;
    vec2 span = coarse_span(parent[a], ratio, fine_count);
    cells = uvec2(parent[a]);
    weights = vec2(1.0, 0.0);
    if (x == span.x) {
        return;
    }
    bool below = x < span.x;
    if (below ? parent[a] > 0u : parent[a] + 1u < coarse_count) {
        uint neighbour = below ? parent[a] - 1u : parent[a] + 1u;
        float t = (x - span.x) / (coarse_span(neighbour, ratio, fine_count).x - span.x);
        cells.y = neighbour;
        weights = vec2(1.0 - t, t);
        return;
    }
    uvec3 side = parent;
    side[a] = below ? 0u : coarse_count;
    if (mg_conductance(l + 1u, a, side) > 0.0) {
        weights.x = 1.0 - abs(x - span.x) / span.y;
    }
}

// Weight of coarse cell c (level l + 1) in fine cell f's interpolation:
// the product of the axes' weights.
float mg_weight(uint l, uvec3 f, uvec3 c) {
    uvec3 parent = f / MG_LEVELS[l].ratio;
    float w = 1.0;
    for (uint a = 0u; a < 3u; ++a) {
        uvec2 cells;
        vec2 weights;
        mg_axis_pair(l, f, parent, a, cells, weights);
        w *= c[a] == cells.x ? weights.x : (c[a] == cells.y ? weights.y : 0.0);
    }
    return w;
}

// Restriction from level l: coarse cell `index` of level l + 1 gathers the
// fine residuals (saved before) weighted by the transpose of the
// interpolation (`Level::gather`).
float mg_restricted(uint l, uint index) {
    uvec3 c = mg_cell_of(l + 1u, index);
    uvec3 r = MG_LEVELS[l].ratio;
    uvec3 nf = MG_LEVELS[l].cells;
    uvec3 lo = uvec3(max(ivec3(c * r) - ivec3(r - 1u), ivec3(0)));
    uvec3 hi = min(c * r + r + (r - 1u), nf) - 1u;
    float sum = 0.0;
    for (uint z = lo.z; z <= hi.z; ++z) {
        for (uint y = lo.y; y <= hi.y; ++y) {
            for (uint x = lo.x; x <= hi.x; ++x) {
                uvec3 f = uvec3(x, y, z);
                float w = mg_weight(l, f, c);
                if (w != 0.0) {
                    sum += w * MG_SAVED_RESIDUAL(mg_cell_index(l, f));
                }
            }
        }
    }
    return sum;
}

// Prolongation to level l: the trilinear interpolation of level l + 1's
// correction at fine cell `index`'s centre (`Level::interpolation`).
float mg_prolonged(uint l, uint index) {
    uvec3 f = mg_cell_of(l, index);
    uvec3 parent = f / MG_LEVELS[l].ratio;
    uvec2 cx, cy, cz;
    vec2 wx, wy, wz;
    mg_axis_pair(l, f, parent, 0u, cx, wx);
    mg_axis_pair(l, f, parent, 1u, cy, wy);
    mg_axis_pair(l, f, parent, 2u, cz, wz);
    float sum = 0.0;
    for (uint k = 0u; k < 2u; ++k) {
        for (uint j = 0u; j < 2u; ++j) {
            for (uint i = 0u; i < 2u; ++i) {
                float w = wx[i] * wy[j] * wz[k];
                if (w != 0.0) {
                    sum += w * MG_P(l + 1u, mg_cell_index(l + 1u, uvec3(cx[i], cy[j], cz[k])));
                }
            }
        }
    }
    return sum;
}

#endif
