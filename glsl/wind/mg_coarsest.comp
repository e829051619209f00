#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, the coarsest level pc.mg_level (at most 64 cells,
// `MAX_COARSEST_CELLS`; the shared array holds up to 512):
// pc.coarsest_sweeps red-black Gauss-Seidel sweeps in one workgroup, the
// pressure held in shared memory between half-sweeps.
#include "multigrid.glsl"

const uint COARSEST_CAPACITY = 512u;
shared float p_shared[COARSEST_CAPACITY];

void main() {
    uint l = pc.mg_level;
    uint n = mg_cell_count(l);
    uint lane = gl_LocalInvocationID.x;
    for (uint i = lane; i < n; i += gl_WorkGroupSize.x) {
        p_shared[i] = mg_p(l, i);
    }
    barrier();
    uvec3 dims = levels[l].cells.xyz;
    for (uint sweep = 0u; sweep < pc.coarsest_sweeps; ++sweep) {
        for (uint color = 0u; color < 2u; ++color) {
            for (uint i = lane; i < n; i += gl_WorkGroupSize.x) {
                uvec3 c = mg_cell_of(l, i);
                if ((c.x + c.y + c.z) % 2u != color) {
                    continue;
                }
                float diagonal = 0.0;
                float neighbours = 0.0;
                for (uint axis = 0u; axis < 3u; ++axis) {
                    for (uint side = 0u; side < 2u; ++side) {
                        uvec3 f = c;
                        f[axis] += side;
                        float k = mg_conductance(l, axis, f);
                        if (k == 0.0) {
                            continue;
                        }
                        diagonal += k;
                        ivec3 nb = ivec3(c);
                        nb[axis] += side == 1u ? 1 : -1;
                        if (nb[axis] >= 0 && nb[axis] < int(dims[axis])) {
                            neighbours += k * p_shared[mg_cell_index(l, uvec3(nb))];
                        }
                    }
                }
                p_shared[i] = diagonal == 0.0 ? 0.0 : (mg_b(l, i) + neighbours) / diagonal;
            }
            barrier();
        }
    }
    for (uint i = lane; i < n; i += gl_WorkGroupSize.x) {
        mg_set_p(l, i, p_shared[i]);
    }
}
