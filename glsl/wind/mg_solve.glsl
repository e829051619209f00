// The multigrid solve's control (mirrors `Multigrid::solve` in
// src/model/multigrid.rs): the solve buffer, level 0's residual norms
// summed by one workgroup in a fixed order, and the V-cycle's indirect
// dispatches switched off once the residual is small enough.
#ifndef MEADOW_MG_SOLVE_GLSL
#define MEADOW_MG_SOLVE_GLSL

#define WIND_KERNEL_GROUP MG_CHECK_GROUP
#include "multigrid.glsl"

// MgSolve: src/interface/defs.rs. args: solve.dispatches live ones, then
// the same as made.
layout(set = 0, binding = 13, std430) buffer Solve {
    MgSolve solve;
    uvec4 args[];
};

// The pressure copies: 0 the solve's, 1 the saved residual (Jacobi's
// pong), 2 the last step's (the extrapolation's p_(n-1)).
const uint MG_BEFORE = 2u;

// A q at level 0's cell `index`, q the pressure copy starting at `base`:
// the 6-point stencil as `Operators::residual` sums it.
float mg_apply(uint base, uint index) {
    float k[6];
    uint nb[6];
    bool inside[6];
    mg_stencil_terms(0u, mg_cell_of(0u, index), k, nb, inside);
    float diagonal = 0.0;
    float neighbours = 0.0;
    for (uint t = 0u; t < 6u; ++t) {
        diagonal += k[t];
        if (inside[t]) {
            neighbours += k[t] * pressure[base + nb[t]];
        }
    }
    return diagonal * pressure[base + index] - neighbours;
}

shared vec3 mg_partial[MG_CHECK_GROUP];

// The workgroup's sum of `value` over its threads (a fixed tree: the same
// bits every run); every thread gets it.
vec3 mg_group_sum(vec3 value) {
    uint t = gl_LocalInvocationID.x;
    mg_partial[t] = value;
    barrier();
    for (uint half_ = MG_CHECK_GROUP / 2u; half_ > 0u; half_ /= 2u) {
        if (t < half_) {
            mg_partial[t] += mg_partial[t + half_];
        }
        barrier();
    }
    vec3 sum = mg_partial[0];
    barrier();
    return sum;
}

// The live dispatches: as made, or none (the residual is small enough).
void mg_set_dispatches(bool run) {
    uint n = solve.dispatches;
    for (uint i = gl_LocalInvocationID.x; i < n; i += MG_CHECK_GROUP) {
        args[i] = run ? args[n + i] : uvec4(0u);
    }
}

#endif
