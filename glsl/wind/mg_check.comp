#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, after a V-cycle (`Multigrid::solve`), in one workgroup:
// unless the solve has already stopped, the cycle counted and the
// residual's share of b's measured; at the tolerance the next V-cycles'
// dispatches are switched off.
#include "mg_solve.glsl"

void main() {
    if (solve.converged != 0u) {
        return;
    }
    uint cells = mg_cell_count(0u);
    vec3 squares = vec3(0.0);
    for (uint i = gl_LocalInvocationID.x; i < cells; i += MG_CHECK_GROUP) {
        float r = mg_b(0u, i) - mg_apply(0u, i);
        squares.x += r * r;
    }
    float left = mg_group_sum(squares).x;
    float b_squares = solve.b_squares;
    bool converged = left <= pc.pressure_tolerance * pc.pressure_tolerance * b_squares;
    if (converged) {
        mg_set_dispatches(false);
    }
    // Every thread read `solve` above; the barrier in mg_group_sum orders
    // those reads before this write.
    if (gl_LocalInvocationID.x == 0u) {
        solve.v_cycles += 1u;
        solve.share_left = b_squares > 0.0 ? sqrt(left / b_squares) : 0.0;
        solve.converged = converged ? 1u : 0u;
    }
}
