#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, one red-black Gauss-Seidel half-sweep on level
// pc.multigrid.x: the cells of colour pc.multigrid.y take the value that
// zeroes their residual (`Level::smooth`).
#include "multigrid.glsl"

void main() {
    uint l = pc.multigrid.x;
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l)) {
        return;
    }
    uvec3 c = mg_cell_of(l, index);
    if ((c.x + c.y + c.z) % 2u != pc.multigrid.y) {
        return;
    }
    vec2 s = mg_stencil(l, c);
    mg_set_p(l, index, s.x == 0.0 ? 0.0 : (mg_b(l, index) + s.y) / s.x);
}
