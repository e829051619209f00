#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 3, divergence of each fluid cell of the advected field B:
// sum over axes of (outgoing face - incoming face) / h. It also carries
// the last step's pressure into copy 0, the Jacobi iterations' start
// (warm start; src/model/wind/projection.rs `solve_pressure`); the
// multigrid's start is mg_start.comp's choice.
#include "wind_kernel.glsl"

void main() {
    uint c = gl_GlobalInvocationID.x;
    uint cells = cell_count();
    if (c >= cells) {
        return;
    }
    if (pc.pressure_result == 1u) {
        pressure[c] = pressure[cells + c];
    }
    if (solid[c] != 0u) {
        divergence[c] = 0.0;
        return;
    }
    uvec3 n = pc.grid.cells.xyz;
    uvec3 cell = uvec3(c % n.x, (c / n.x) % n.y, c / (n.x * n.y));
    uint faces = pc.grid.faces;
    float div = 0.0;
    for (uint axis = 0u; axis < 3u; ++axis) {
        uvec3 hi = cell;
        hi[axis] += 1u;
        float a = vel[faces + face_index(pc.grid, axis, cell)];
        float b = vel[faces + face_index(pc.grid, axis, hi)];
        div += (b - a) / pc.grid.cell_size[axis];
    }
    divergence[c] = div;
}
