#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 2, semi-Lagrangian advection (Stam 1999): each free face traces
// back by dt along the velocity there and takes the value found (A -> B);
// with two-way coupling the canopy drag then slows it, implicitly, by the
// speed at the face: u' = u / (1 + dt C_d a |u|) (`WindField::advect`).
#include "wind_kernel.glsl"
#define WIND_VELOCITY(i) vel[(i)]
#include "wind_sample.glsl"

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
    vec3 v = sample_wind(pc.grid, x);
    vec3 back = x - pc.dt * v;
    float u = sample_component(pc.grid, axis, back);
    // Air traced back beyond an inflow's entry side across the other
    // horizontal axis comes in with the inflow's velocity (`Inflow::entering`).
    vec2 d = inflow_heading();
    if (pc.inflow_speed != 0.0 && axis != 1u && (axis == 0u ? d.x : d.y) != 0.0) {
        uint across = 2u - axis;
        float component = (pc.inflow_speed >= 0.0 ? 1.0 : -1.0) * (across == 0u ? d.x : d.y);
        vec3 lo = pc.grid.origin.xyz;
        vec3 hi = lo + vec3(pc.grid.cells.xyz) * pc.grid.cell_size.xyz;
        bool outside = component != 0.0
            && (component > 0.0 ? back[across] < lo[across] : back[across] > hi[across]);
        if (outside) {
            u = inflow_velocity(axis, clamp(back, lo, hi), pc.time);
        }
    }
    if (pc.canopy_drag > 0.0) {
        // The frontal area per volume at the face: the two cells it parts
        // (the inside one at the grid's sides), `face_canopy_density`.
        uvec3 left = f;
        left[axis] = max(f[axis], 1u) - 1u;
        uvec3 right = f;
        right[axis] = min(f[axis], pc.grid.cells[axis] - 1u);
        float a = (float(canopy[cell_index(pc.grid, left)]) + float(canopy[cell_index(pc.grid, right)]))
                * pc.area_per_count;
        u /= 1.0 + pc.dt * pc.canopy_drag * a * length(v);
    }
    vel[faces + id] = u;
}
