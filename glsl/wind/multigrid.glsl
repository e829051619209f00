// What the multigrid kernels share (mirrors src/sim/multigrid.rs): the
// level table, the pressure and right-hand side of every level, the
// 6-point stencil and the interpolation weights.
#ifndef MEADOW_MULTIGRID_GLSL
#define MEADOW_MULTIGRID_GLSL

#include "wind_kernel.glsl"

struct MgLevel {
    uvec4 cells;        // xyz: cells; w: offset of this level in the coarse arrays
    uvec4 ratio;        // xyz: fine cells per coarse cell towards the next level
    uvec4 conductance;  // xyz: offset of each axis's face conductances
};
layout(set = 0, binding = 6, std430) readonly buffer Conductance { float conductance[]; };
// Coarse levels (1 and up): pressure at [0, C), right-hand side at [C, 2C),
// C = pc.multigrid.w.
layout(set = 0, binding = 7, std430) buffer Coarse { float coarse[]; };
layout(set = 0, binding = 8, std430) readonly buffer Levels { MgLevel levels[]; };

uint mg_cell_count(uint l) {
    uvec3 n = levels[l].cells.xyz;
    return n.x * n.y * n.z;
}

uvec3 mg_cell_of(uint l, uint index) {
    uvec3 n = levels[l].cells.xyz;
    return uvec3(index % n.x, (index / n.x) % n.y, index / (n.x * n.y));
}

uint mg_cell_index(uint l, uvec3 c) {
    uvec3 n = levels[l].cells.xyz;
    return c.x + n.x * (c.y + n.y * c.z);
}

float mg_conductance(uint l, uint axis, uvec3 f) {
    uvec3 d = levels[l].cells.xyz;
    d[axis] += 1u;
    return conductance[levels[l].conductance[axis] + f.x + d.x * (f.y + d.y * f.z)];
}

// Level 0's pressure is the solver's (copy 0); its right-hand side is the
// divergence integrated over the cell, negated.
float mg_p(uint l, uint index) {
    return l == 0u ? pressure[index] : coarse[levels[l].cells.w + index];
}

void mg_set_p(uint l, uint index, float value) {
    if (l == 0u) {
        pressure[index] = value;
    } else {
        coarse[levels[l].cells.w + index] = value;
    }
}

float mg_b(uint l, uint index) {
    if (l == 0u) {
        vec3 h = pc.grid.cell_size.xyz;
        return -divergence[index] * h.x * h.y * h.z;
    }
    return coarse[pc.multigrid.w + levels[l].cells.w + index];
}

// The 6-point stencil at cell c: x = sum of K, y = sum of K * p_nb.
vec2 mg_stencil(uint l, uvec3 c) {
    uvec3 n = levels[l].cells.xyz;
    vec2 s = vec2(0.0);
    for (uint axis = 0u; axis < 3u; ++axis) {
        for (uint side = 0u; side < 2u; ++side) {
            uvec3 f = c;
            f[axis] += side;
            float k = mg_conductance(l, axis, f);
            if (k == 0.0) {
                continue;
            }
            s.x += k;
            ivec3 nb = ivec3(c);
            nb[axis] += side == 1u ? 1 : -1;
            if (nb[axis] >= 0 && nb[axis] < int(n[axis])) {
                s.y += k * mg_p(l, mg_cell_index(l, uvec3(nb)));
            }
        }
    }
    return s;
}

float mg_residual(uint l, uint index) {
    vec2 s = mg_stencil(l, mg_cell_of(l, index));
    return mg_b(l, index) - (s.x * mg_p(l, index) - s.y);
}

// Centre and width of coarse cell c along one axis, in fine cells.
vec2 coarse_span(uint c, uint ratio, uint fine_count) {
    uint start = c * ratio;
    uint end = min(start + ratio, fine_count);
    return vec2(float(start + end) * 0.5, float(end - start));
}

// `axis_weight` in src/sim/multigrid.rs.
float axis_weight(uint fine, uint c, uint ratio, uint fine_count, bool open_side) {
    uint parent = fine / ratio;
    float x = float(fine) + 0.5;
    vec2 span = coarse_span(parent, ratio, fine_count);
    uint coarse_count = (fine_count + ratio - 1u) / ratio;
    int neighbour;
    if (x < span.x) {
        neighbour = int(parent) - 1;
    } else if (x > span.x) {
        neighbour = int(parent) + 1;
        if (neighbour >= int(coarse_count)) {
            neighbour = -1;
        }
    } else {
        return c == parent ? 1.0 : 0.0;
    }
    if (neighbour >= 0) {
        float other = coarse_span(uint(neighbour), ratio, fine_count).x;
        float t = (x - span.x) / (other - span.x);
        return c == parent ? 1.0 - t : (c == uint(neighbour) ? t : 0.0);
    }
    if (c != parent) {
        return 0.0;
    }
    return open_side ? 1.0 - abs(x - span.x) / span.y : 1.0;
}

// Weight of coarse cell c (level l + 1) in fine cell f's (level l) interpolation.
float mg_weight(uint l, uvec3 f, uvec3 c) {
    uvec3 r = levels[l].ratio.xyz;
    uvec3 nf = levels[l].cells.xyz;
    uvec3 nc = levels[l + 1u].cells.xyz;
    uvec3 parent = f / r;
    float w = 1.0;
    for (uint a = 0u; a < 3u; ++a) {
        float centre = coarse_span(parent[a], r[a], nf[a]).x;
        uvec3 side = parent;
        side[a] = float(f[a]) + 0.5 < centre ? 0u : nc[a];
        bool open_side = mg_conductance(l + 1u, a, side) > 0.0;
        w *= axis_weight(f[a], c[a], r[a], nf[a], open_side);
    }
    return w;
}

#endif
