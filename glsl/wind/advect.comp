#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 2, the paper's semi-Lagrangian advection (advect.glsl), A -> B,
// with the canopy drag.
#include "advect.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint faces = pc.grid.faces;
    if (id >= faces) {
        return;
    }
    if (face_kind[id] != FACE_FREE) {
        vel[faces + id] = vel[id];
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    vec3 x = face_position(pc.grid, axis, f);
    vec3 v = wind_at(x);
    bool entered;
    float u = traced_back(axis, x, v, entered);
    vel[faces + id] = with_canopy_drag(u, axis, f, v);
}
