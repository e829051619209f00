#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, the residual b - A p of every cell of level pc.mg_level,
// saved once for the restriction, which reads each up to eight times.
#include "multigrid.glsl"

void main() {
    uint l = mg_level();
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l)) {
        return;
    }
    mg_save_residual(index, mg_residual(l, index));
}
