#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, a step's start (`Multigrid::solve`), in one workgroup: of
// zero, the last step's pressure p and the last two carried on,
// 2 p - p_(n-1), the one with the smallest residual; the last pressure
// kept as p_(n-1) for the next step; the last step's V-cycles counted in
// the histogram; the V-cycles' dispatches switched on unless the start
// already meets the tolerance.
#include "mg_solve.glsl"

void main() {
    uint cells = mg_cell_count(0u);
    uint before = MG_BEFORE * cells;
    // x: b^2, y: (b - A p)^2, z: (b - A (2 p - q))^2.
    vec3 squares = vec3(0.0);
    for (uint i = gl_LocalInvocationID.x; i < cells; i += MG_CHECK_GROUP) {
        float b = mg_b(0u, i);
        float ap = mg_apply(0u, i);
        float aq = mg_apply(before, i);
        float last = b - ap;
        float extrapolated = b - (2.0 * ap - aq);
        squares += vec3(b * b, last * last, extrapolated * extrapolated);
    }
    vec3 sum = mg_group_sum(squares);
    uint start = sum.z < sum.y && sum.z < sum.x ? 2u : (sum.y < sum.x ? 1u : 0u);
    float left = start == 2u ? sum.z : (start == 1u ? sum.y : sum.x);
    // Every thread read its cells' neighbours above; the barrier in
    // mg_group_sum orders those reads before these writes.
    for (uint i = gl_LocalInvocationID.x; i < cells; i += MG_CHECK_GROUP) {
        float p = pressure[i];
        float q = pressure[before + i];
        pressure[before + i] = p;
        pressure[i] = start == 2u ? 2.0 * p - q : (start == 1u ? p : 0.0);
    }
    float goal = pc.pressure_tolerance * pc.pressure_tolerance * sum.x;
    bool converged = left <= goal;
    mg_set_dispatches(!converged);
    if (gl_LocalInvocationID.x == 0u) {
        if (solve.steps > 0u) {
            solve.histogram[min(solve.v_cycles, uint(MG_HISTOGRAM) - 1u)] += 1u;
        }
        solve.steps += 1u;
        solve.v_cycles = 0u;
        solve.start = start;
        solve.b_squares = sum.x;
        solve.share_left = sum.x > 0.0 ? sqrt(left / sum.x) : 0.0;
        solve.converged = converged ? 1u : 0u;
    }
}
