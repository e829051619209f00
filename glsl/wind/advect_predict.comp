#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 2a, MacCormack's predictor (advect.glsl): the semi-Lagrangian
// value of every free face, A -> C; the fixed faces copied, for the
// corrector's forward trace to read.
#include "advect.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint faces = pc.grid.faces;
    if (id >= faces) {
        return;
    }
    if (face_kind[id] != FACE_FREE) {
        vel[2u * faces + id] = vel[id];
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    vec3 x = face_position(pc.grid, axis, f);
    bool entered;
    vel[2u * faces + id] = traced_back(axis, x, wind_at(x), entered);
}
