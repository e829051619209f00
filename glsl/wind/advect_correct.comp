#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 2b, MacCormack's corrector (advect.glsl), A and C -> B: the
// predictor's value traced forward again through C, half the difference
// from A's value added, clamped to the range of the eight values of A the
// back trace interpolated (no new extremes); air that came in across an
// entry side keeps the inflow's value. Then the canopy drag.
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
    float u = vel[2u * faces + id];
    float from_inflow;
    if (!entering(axis, x - pc.dt * v, from_inflow)) {
        sampled_copy = 2u * faces;
        float again = sample_component(pc.grid, axis, x + pc.dt * v);
        sampled_copy = 0u;
        vec2 range = sample_range(pc.grid, axis, x - pc.dt * v);
        u = min(max(u + 0.5 * (vel[id] - again), range.x), range.y);
    }
    vel[faces + id] = with_canopy_drag(u, axis, f, v);
}
