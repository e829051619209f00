// Kernel 2, advection (`WindField::advect`): what the three advection
// kernels share. A free face traces back by dt along the velocity there and
// takes the value found (semi-Lagrangian, Stam 1999: advect.comp, the
// paper's); MacCormack's predictor stores that value in copy C
// (advect_predict.comp) and its corrector (advect_correct.comp) traces it
// forward again, adds half the difference from the value it started with
// and clamps the sum to the range the back trace interpolated. With
// two-way coupling the canopy drag then slows the result, implicitly, by
// the speed at the face: u' = u / (1 + dt C_d a |u|).
#ifndef MEADOW_ADVECT_GLSL
#define MEADOW_ADVECT_GLSL
#include "wind_kernel.glsl"

// Where the copy the samplers read starts: A (0) or C (2 F, the predictor's).
uint sampled_copy = 0u;
#define WIND_VELOCITY(i) vel[sampled_copy + (i)]
#include "wind_sample.glsl"

// Whether air traced back to `back` from a face of component `axis` comes
// in across the inflow's entry side of the other horizontal axis, and then
// the inflow's velocity (`Inflow::entering`).
bool entering(uint axis, vec3 back, out float u) {
    u = 0.0;
    vec2 d = inflow_heading();
    if (pc.inflow_speed == 0.0 || axis == 1u || (axis == 0u ? d.x : d.y) == 0.0) {
        return false;
    }
    uint across = 2u - axis;
    float component = (pc.inflow_speed >= 0.0 ? 1.0 : -1.0) * (across == 0u ? d.x : d.y);
    vec3 lo = pc.grid.origin.xyz;
    vec3 hi = lo + vec3(pc.grid.cells.xyz) * pc.grid.cell_size.xyz;
    bool outside = component != 0.0
        && (component > 0.0 ? back[across] < lo[across] : back[across] > hi[across]);
    if (outside) {
        u = inflow_velocity(axis, clamp(back, lo, hi), pc.time);
    }
    return outside;
}

// The semi-Lagrangian value of the face at x of component `axis`, traced
// back along v through copy A; `entered`: from outside, across an entry side.
float traced_back(uint axis, vec3 x, vec3 v, out bool entered) {
    vec3 back = x - pc.dt * v;
    float u;
    entered = entering(axis, back, u);
    if (!entered) {
        sampled_copy = 0u;
        u = sample_component(pc.grid, axis, back);
    }
    return u;
}

// u slowed by the canopy drag at face f, by the speed |v| there: the
// frontal area per volume of the two cells it parts (the inside one at
// the grid's sides), `face_canopy_density`.
float with_canopy_drag(float u, uint axis, uvec3 f, vec3 v) {
    if (pc.canopy_drag <= 0.0) {
        return u;
    }
    uvec3 left = f;
    left[axis] = max(f[axis], 1u) - 1u;
    uvec3 right = f;
    right[axis] = min(f[axis], pc.grid.cells[axis] - 1u);
    float a = (float(canopy[cell_index(pc.grid, left)]) + float(canopy[cell_index(pc.grid, right)]))
            * pc.area_per_count;
    return u / (1.0 + pc.dt * pc.canopy_drag * a * length(v));
}

// The velocity at face x, from copy A.
vec3 wind_at(vec3 x) {
    sampled_copy = 0u;
    return sample_wind(pc.grid, x);
}
#endif
