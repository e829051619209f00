#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 6, with terrain (`WindField::free_slip_under_ground`): each buried
// face, a horizontal component between two cells under the ground, takes
// the value of the first free face above it in its column, so that the
// samplers (advection's trace, a blade tip's wind) see free slip over the
// staircase instead of the zeros under it. Reads free faces, writes buried
// ones: no invocation reads what another writes.
#include "wind_kernel.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.grid.faces || face_kind[id] != FACE_BURIED) {
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    float u = 0.0;
    for (uint up = f.y + 1u; up < pc.grid.cells.y; ++up) {
        uint above = face_index(pc.grid, axis, uvec3(f.x, up, f.z));
        if (face_kind[above] == FACE_FREE) {
            u = vel[above];
            break;
        }
    }
    vel[id] = u;
}
