#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, restriction from level pc.mg_level to the next: each coarse
// cell gathers the fine residuals weighted by the transpose of the
// interpolation (saved by mg_residual.comp), and its correction starts
// from zero (`Multigrid::v_cycle`).
#include "multigrid.glsl"

void main() {
    uint l = pc.mg_level;
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l + 1u)) {
        return;
    }
    uvec3 c = mg_cell_of(l + 1u, index);
    uvec3 r = levels[l].ratio.xyz;
    uvec3 nf = levels[l].cells.xyz;
    uvec3 lo = uvec3(max(ivec3(c * r) - ivec3(r - 1u), ivec3(0)));
    uvec3 hi = min(c * r + r + (r - 1u), nf) - 1u;
    float sum = 0.0;
    for (uint z = lo.z; z <= hi.z; ++z) {
        for (uint y = lo.y; y <= hi.y; ++y) {
            for (uint x = lo.x; x <= hi.x; ++x) {
                uvec3 f = uvec3(x, y, z);
                float w = mg_weight(l, f, c);
                if (w != 0.0) {
                    sum += w * mg_saved_residual(mg_cell_index(l, f));
                }
            }
        }
    }
    uint at = levels[l + 1u].cells.w + index;
    coarse[pc.coarse_cells + at] = sum;
    coarse[at] = 0.0;
}
