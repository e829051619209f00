// What every wind kernel binds: push constants and the solver's buffers.
// Mirrors `WindPush` and `GpuWindSource` in src/render/wind_pass.rs.
#ifndef MEADOW_WIND_KERNEL_GLSL
#define MEADOW_WIND_KERNEL_GLSL

#include "wind_grid.glsl"

layout(local_size_x = 64) in;

layout(push_constant, std430) uniform Push {
    WindGridParams grid;
    vec4 step;           // x: time (s), y: dt (s), z: canopy drag C_d (0: one-way),
                         // w: frontal area per volume (1/m) of one count on each side of a face
    uvec4 control;       // x: source count, y: pressure half to read, z: pressure half holding the result,
                         // w: 1 when the pressure starts from zero (multigrid)
    vec4 inflow;         // x: speed (m/s), y: gust amplitude, z: gust frequency (Hz)
    vec4 inflow_phases;  // xyz: gust phases; w: colliders pushing the air (forces kernel)
    uvec4 multigrid;     // x: level, y: colour, z: coarsest sweeps, w: coarse cells of all levels
} pc;

// Two copies of the velocity: A = [0, F) is the state between steps,
// B = [F, 2F) the advected field. F = pc.grid.cells.w.
layout(set = 0, binding = 0, std430) buffer Velocity { float vel[]; };
layout(set = 0, binding = 1, std430) readonly buffer Faces { uint face_kind[]; };
layout(set = 0, binding = 2, std430) readonly buffer Solid { uint solid[]; };
// Two copies for the Jacobi ping-pong.
layout(set = 0, binding = 3, std430) buffer Pressure { float pressure[]; };
layout(set = 0, binding = 4, std430) buffer Divergence { float divergence[]; };

struct WindSource {
    vec4 position_radius;     // xyz: position at t = 0; w: radius (m)
    vec4 direction_strength;  // xyz: unit direction at t = 0; w: strength (m/s^2)
    vec4 motion;              // x: rotation speed (rad/s), y: path speed (m/s), z: path points, w: off after (s)
    vec4 gust;                // x: amplitude, y: frequency (Hz)
    vec4 gust_phases;         // xyz
    vec4 path[8];             // xyz: waypoints of the closed path (PATH_POINTS in path.glsl)
};
layout(set = 0, binding = 5, std430) readonly buffer Sources { WindSource sources[]; };
// The grass's frontal area per cell in counts (src/sim/canopy.rs), laid by
// the grass step with two-way coupling. Bindings 6-8 are the multigrid's.
layout(set = 0, binding = 9, std430) readonly buffer Canopy { uint canopy[]; };

const float TAU = 6.2831853071795864;

// g at time t, each harmonic delayed by its own delay (s); `Gust::signal`.
float gust_signal(float frequency, vec3 phases, float t, vec3 delay) {
    return 0.5 * sin(TAU * frequency * 1.0 * (t - delay.x) + phases.x)
         + 0.3 * sin(TAU * frequency * 2.17 * (t - delay.y) + phases.y)
         + 0.2 * sin(TAU * frequency * 4.73 * (t - delay.z) + phases.z);
}

// Strength factor over time (src/sim/wind.rs `Gust::factor`).
float gust_factor(float amplitude, float frequency, vec3 phases, float t) {
    if (amplitude == 0.0) {
        return 1.0;
    }
    return max(1.0 + amplitude * gust_signal(frequency, phases, t, vec3(0.0)), 0.0);
}

// `INFLOW_GUST_LEAN` and its signs in src/sim/wind.rs.
const float INFLOW_GUST_LEAN = 0.5;
const vec3 INFLOW_GUST_LEAN_SIGN = vec3(1.0, -1.0, 1.0);

// The inflow velocity at height y above the grid's floor, at z, at time t
// (`Inflow::velocity_at`): u = U (1 + a g(t - lean z / |U|) cos(pi y / H)),
// the same flux at every instant, gusts carried downwind by advection.
float inflow_velocity(float y, float z, float t) {
    float speed = pc.inflow.x;
    float amplitude = pc.inflow.y;
    if (amplitude == 0.0) {
        return speed;
    }
    float height = float(pc.grid.cells.y) * pc.grid.cell_size.y;
    float lean = INFLOW_GUST_LEAN * z / max(abs(speed), 1e-3);
    float g = gust_signal(pc.inflow.z, pc.inflow_phases.xyz, t, INFLOW_GUST_LEAN_SIGN * lean);
    return speed * (1.0 + amplitude * g * cos(0.5 * TAU * y / height));
}

uint cell_count() {
    return pc.grid.cells.x * pc.grid.cells.y * pc.grid.cells.z;
}

#endif
