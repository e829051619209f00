#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, prolongation to level pc.mg_level: every fine cell adds the
// trilinear interpolation of the next level's correction at its centre.
#include "multigrid.glsl"

void main() {
    uint l = mg_level();
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l)) {
        return;
    }
    mg_set_p(l, index, mg_p(l, index) + mg_prolonged(l, index));
}
