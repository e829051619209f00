#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 2, semi-Lagrangian advection (Stam 1999): each free face traces
// back by dt along the velocity there and takes the value found (A -> B).
#include "wind_kernel.glsl"
#define WIND_VELOCITY(i) vel[(i)]
#include "wind_sample.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint faces = pc.grid.cells.w;
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
    vec3 back = x - pc.step.y * sample_wind(pc.grid, x);
    vel[faces + id] = sample_component(pc.grid, axis, back);
}
