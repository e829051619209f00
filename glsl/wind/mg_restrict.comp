#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, restriction from level pc.mg_level to the next: each coarse
// cell gathers the fine residuals weighted by the transpose of the
// interpolation (saved by mg_residual.comp), and its correction starts
// from zero (`Multigrid::v_cycle`).
#include "multigrid.glsl"

void main() {
    uint l = mg_level();
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l + 1u)) {
        return;
    }
    uint at = levels[l + 1u].coarse_offset + index;
    coarse[pc.coarse_cells + at] = mg_restricted(l, index);
    coarse[at] = 0.0;
}
