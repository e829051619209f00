#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, prolongation to level pc.multigrid.x: every fine cell adds the
// trilinear interpolation of the next level's correction at its centre.
#include "multigrid.glsl"

void main() {
    uint l = pc.multigrid.x;
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l)) {
        return;
    }
    uvec3 f = mg_cell_of(l, index);
    uvec3 parent = f / levels[l].ratio.xyz;
    uvec3 nc = levels[l + 1u].cells.xyz;
    uvec3 lo = uvec3(max(ivec3(parent) - 1, ivec3(0)));
    uvec3 hi = min(parent + 1u, nc - 1u);
    float sum = 0.0;
    for (uint z = lo.z; z <= hi.z; ++z) {
        for (uint y = lo.y; y <= hi.y; ++y) {
            for (uint x = lo.x; x <= hi.x; ++x) {
                uvec3 c = uvec3(x, y, z);
                float w = mg_weight(l, f, c);
                if (w != 0.0) {
                    sum += w * mg_p(l + 1u, mg_cell_index(l + 1u, c));
                }
            }
        }
    }
    mg_set_p(l, index, mg_p(l, index) + sum);
}
