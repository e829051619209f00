#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 5, projection: subtract the pressure gradient from every free face
// of B, (p_right - p_left) / h with p = 0 outside an open side, into A.
#include "wind_kernel.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint faces = pc.grid.faces;
    if (id >= faces) {
        return;
    }
    if (face_kind[id] != FACE_FREE) {
        vel[id] = vel[faces + id];
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    uint p = pc.pressure_result * cell_count();
    uvec3 n = pc.grid.cells.xyz;
    float p_right = f[axis] < n[axis] ? pressure[p + cell_index(pc.grid, f)] : 0.0;
    float p_left = 0.0;
    if (f[axis] > 0u) {
        uvec3 l = f;
        l[axis] -= 1u;
        p_left = pressure[p + cell_index(pc.grid, l)];
    }
    vel[id] = vel[faces + id] - (p_right - p_left) / pc.grid.cell_size[axis];
}
