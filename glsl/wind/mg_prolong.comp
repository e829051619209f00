#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, prolongation to level pc.mg_level: every fine cell adds the
// trilinear interpolation of the next level's correction at its centre.
#include "multigrid.glsl"

void main() {
    uint l = pc.mg_level;
    uint index = gl_GlobalInvocationID.x;
    if (index >= mg_cell_count(l)) {
        return;
    }
    uvec3 f = mg_cell_of(l, index);
    uvec3 parent = f / levels[l].ratio.xyz;
    uvec2 cx, cy, cz;
    vec2 wx, wy, wz;
    mg_axis_pair(l, f, parent, 0u, cx, wx);
    mg_axis_pair(l, f, parent, 1u, cy, wy);
    mg_axis_pair(l, f, parent, 2u, cz, wz);
    float sum = 0.0;
    for (uint k = 0u; k < 2u; ++k) {
        for (uint j = 0u; j < 2u; ++j) {
            for (uint i = 0u; i < 2u; ++i) {
                float w = wx[i] * wy[j] * wz[k];
                if (w != 0.0) {
                    sum += w * mg_p(l + 1u, mg_cell_index(l + 1u, uvec3(cx[i], cy[j], cz[k])));
                }
            }
        }
    }
    mg_set_p(l, index, mg_p(l, index) + sum);
}
