#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 7, with turbulence (`WindField::add_turbulence`,
// src/model/turbulence.rs): every free, buried and inflow face gains the
// sum of the Fourier modes at the step's end, and keeps what it gained in
// `turbulence_added` for the next step's forces kernel to take off (an
// inflow face is set anew there). The modes are written before each step
// with their phases then. Beside a solid cell a face takes the curl of the
// modes' potential held at zero on the solid's edges.
#include "wind_kernel.glsl"
#include "turbulence.glsl"

// TurbulenceMode: src/interface/defs.rs.
layout(set = 0, binding = 12, std430) readonly buffer Modes { TurbulenceMode modes[]; };


// Whether the edge along `component` at half-cell point p touches a solid
// cell (`edge_touches_solid` in src/model/wind.rs): the cell it runs
// through, and those either side across each other axis.
bool edge_touches_solid(uint component, uvec3 p) {
    uvec3 n = pc.grid.cells.xyz;
    uvec3 lo;
    uvec3 hi;
    for (uint d = 0u; d < 3u; ++d) {
        if (d == component) {
            lo[d] = (p[d] - 1u) / 2u;
            hi[d] = lo[d];
        } else {
            uint g = p[d] / 2u;
            lo[d] = g > 0u ? g - 1u : 0u;
            hi[d] = min(g, n[d] - 1u);
        }
    }
    for (uint k = lo.z; k <= hi.z; ++k) {
        for (uint j = lo.y; j <= hi.y; ++j) {
            for (uint i = lo.x; i <= hi.x; ++i) {
                if (solid[cell_index(pc.grid, uvec3(i, j, k))] != 0u) {
                    return true;
                }
            }
        }
    }
    return false;
}

// The modes' potential along `component` at the edge of half-cell point p,
// held at zero where the edge touches a solid cell.
float held_potential(uint component, uvec3 p) {
    if (edge_touches_solid(component, p)) {
        return 0.0;
    }
    vec3 x = vec3(p) * 0.5 * pc.grid.cell_size.xyz;
    float psi = 0.0;
    for (uint n = 0u; n < uint(modes.length()); ++n) {
        psi += turbulence_potential(modes[n], component, x);
    }
    return psi;
}

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.grid.faces) {
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    // Walls gain nothing, but for those on the sides across an axis the
    // modes are not mirrored across, before a cell of air (a moving
    // window's sides along the wind; `add_turbulence_now`): the next
    // step's forces wall them again.
    if (face_kind[id] == FACE_WALL) {
        uvec3 n = pc.grid.cells.xyz;
        uvec3 c = f;
        c[axis] = min(c[axis], n[axis] - 1u);
        bool open_side = axis != 1u && (f[axis] == 0u || f[axis] == n[axis])
            && (modes[0].mirrored & (1u << axis)) == 0u
            && solid[cell_index(pc.grid, c)] == 0u;
        if (!open_side) {
            return;
        }
    }
    // The face's half-cell point (`TurbulenceField::face_point`): 2 f
    // along its axis, 2 f + 1 across.
    uvec3 q = 2u * f + 1u;
    q[axis] -= 1u;
    // Beside a solid cell, the curl of the potential held at zero on the
    // edges touching it (`TurbulenceField::curl_at`): no flow into the
    // solid, no divergence beside it. A buried face is a ghost value.
    uint b = (axis + 1u) % 3u;
    uint c = (axis + 2u) % 3u;
    uvec3 eb = uvec3(0u);
    eb[b] = 1u;
    uvec3 ec = uvec3(0u);
    ec[c] = 1u;
    bool beside_solid = face_kind[id] != FACE_BURIED
        && (edge_touches_solid(c, q + eb) || edge_touches_solid(c, q - eb)
            || edge_touches_solid(b, q + ec) || edge_touches_solid(b, q - ec));
    float u = 0.0;
    if (beside_solid) {
        vec3 h = pc.grid.cell_size.xyz;
        u = (held_potential(c, q + eb) - held_potential(c, q - eb)) / h[b]
            - (held_potential(b, q + ec) - held_potential(b, q - ec)) / h[c];
    } else {
        vec3 x = vec3(q) * 0.5 * pc.grid.cell_size.xyz;
        for (uint n = 0u; n < uint(modes.length()); ++n) {
            u += turbulence_component(modes[n], axis, x);
        }
    }
    vel[id] += u;
    turbulence_added[id] = u;
}
