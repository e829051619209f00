#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, one red-black Gauss-Seidel half-sweep on level
// pc.mg_level: the cells of colour pc.mg_sweep take the value that
// zeroes their residual (`Level::smooth`). One thread per cell of that
// colour.
#include "multigrid.glsl"

void main() {
    uint l = mg_level();
    uvec3 c;
    if (!mg_cell_of_color(l, gl_GlobalInvocationID.x, pc.mg_sweep, c)) {
        return;
    }
    mg_set_p(l, mg_cell_index(l, c), mg_smoothed(l, c));
}
