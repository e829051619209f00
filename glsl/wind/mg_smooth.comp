#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, one red-black Gauss-Seidel half-sweep on level
// pc.mg_level: the cells of colour pc.mg_color take the value that
// zeroes their residual (`Level::smooth`). One thread per cell of that
// colour.
#include "multigrid.glsl"

void main() {
    uint l = pc.mg_level;
    uvec3 c;
    if (!mg_cell_of_color(l, gl_GlobalInvocationID.x, pc.mg_color, c)) {
        return;
    }
    uint index = mg_cell_index(l, c);
    vec2 s = mg_stencil(l, c);
    mg_set_p(l, index, s.x == 0.0 ? 0.0 : (mg_b(l, index) + s.y) / s.x);
}
