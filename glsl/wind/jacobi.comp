#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 4, one Jacobi iteration of the pressure Poisson equation:
// sum over free faces of (p_nb - p) / h^2 = div. Across a wall or inflow
// face the term drops (Neumann); outside an open side p = 0 (Dirichlet).
#include "wind_kernel.glsl"

void main() {
    uint c = gl_GlobalInvocationID.x;
    uint cells = cell_count();
    if (c >= cells) {
        return;
    }
    uint read = pc.pressure_read * cells;
    uint write = (1u - pc.pressure_read) * cells;
    if (solid[c] != 0u) {
        pressure[write + c] = 0.0;
        return;
    }
    uvec3 n = pc.grid.cells.xyz;
    uvec3 cell = uvec3(c % n.x, (c / n.x) % n.y, c / (n.x * n.y));
    float sum = 0.0;
    float weight = 0.0;
    for (uint axis = 0u; axis < 3u; ++axis) {
        float inv_h2 = 1.0 / (pc.grid.cell_size[axis] * pc.grid.cell_size[axis]);
        for (uint side = 0u; side < 2u; ++side) {
            uvec3 f = cell;
            f[axis] += side;
            if (face_kind[face_index(pc.grid, axis, f)] != FACE_FREE) {
                continue;
            }
            ivec3 nb = ivec3(cell);
            nb[axis] += side == 1u ? 1 : -1;
            bool outside = nb[axis] < 0 || nb[axis] >= int(n[axis]);
            float p_nb = outside ? 0.0 : pressure[read + cell_index(pc.grid, uvec3(nb))];
            sum += p_nb * inv_h2;
            weight += inv_h2;
        }
    }
    pressure[write + c] = weight == 0.0 ? 0.0 : (sum - divergence[c]) / weight;
}
