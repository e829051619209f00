// What every wind kernel binds: push constants and the solver's buffers.
// The push constants (`WindPush`) and the sources (`GpuWindSource`) are
// src/interface/defs.rs's.
#ifndef MEADOW_WIND_KERNEL_GLSL
#define MEADOW_WIND_KERNEL_GLSL

#include "wind_grid.glsl"

// A kernel of another size (mg_tail.glsl) defines WIND_KERNEL_GROUP first.
#ifndef WIND_KERNEL_GROUP
#define WIND_KERNEL_GROUP WIND_GROUP
#endif
layout(local_size_x = WIND_KERNEL_GROUP) in;

// WindPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    WindPush pc;
};

// Copies of the velocity: A = [0, F) is the state between steps,
// B = [F, 2F) the advected field, and with MacCormack's advection
// C = [2F, 3F) its predictor. F = pc.grid.faces.
layout(set = 0, binding = 0, std430) buffer Velocity { float vel[]; };
layout(set = 0, binding = 1, std430) readonly buffer Faces { uint face_kind[]; };
layout(set = 0, binding = 2, std430) readonly buffer Solid { uint solid[]; };
// Two copies for the Jacobi ping-pong.
layout(set = 0, binding = 3, std430) buffer Pressure { float pressure[]; };
layout(set = 0, binding = 4, std430) buffer Divergence { float divergence[]; };

// GpuWindSource: src/interface/defs.rs.
layout(set = 0, binding = 5, std430) readonly buffer Sources { GpuWindSource sources[]; };
// The grass's frontal area per cell in counts (src/model/canopy.rs), laid by
// the grass step with two-way coupling. Bindings 6-8 are the multigrid's.
layout(set = 0, binding = 9, std430) readonly buffer Canopy { uint canopy[]; };
// Binding 10: the colliders (forces.comp). What the last step's turbulence
// added to each face (zero without turbulence), taken off again by the
// next step's forces kernel (turbulence.comp). Binding 12: its modes.
layout(set = 0, binding = 11, std430) buffer TurbulenceAdded { float turbulence_added[]; };

const float TAU = 6.2831853071795864;

// g at time t, each harmonic delayed by its own delay (s); `Gust::signal`.
float gust_signal(float frequency, vec3 phases, float t, vec3 delay) {
    return 0.5 * sin(TAU * frequency * 1.0 * (t - delay.x) + phases.x)
         + 0.3 * sin(TAU * frequency * 2.17 * (t - delay.y) + phases.y)
         + 0.2 * sin(TAU * frequency * 4.73 * (t - delay.z) + phases.z);
}

// Strength factor over time (src/model/wind/drive.rs `Gust::factor`).
float gust_factor(float amplitude, float frequency, vec3 phases, float t) {
    if (amplitude == 0.0) {
        return 1.0;
    }
    return max(1.0 + amplitude * gust_signal(frequency, phases, t, vec3(0.0)), 0.0);
}

// `INFLOW_GUST_LEAN` and its signs in src/model/wind/drive.rs.
const float INFLOW_GUST_LEAN = 0.5;
const vec3 INFLOW_GUST_LEAN_SIGN = vec3(1.0, -1.0, 1.0);

// The unit vector (x, z) the inflow's heading points along; exactly (1, 0)
// at heading 0 (`Inflow::heading_vector`).
vec2 inflow_heading() {
    float h = pc.inflow_heading;
    if (h == 0.0) {
        return vec2(1.0, 0.0);
    }
    // A component under 1e-6 is the rounding of a heading along an axis.
    vec2 d = vec2(cos(h), sin(h));
    return mix(d, vec2(0.0), lessThan(abs(d), vec2(1e-6)));
}

// The inflow's velocity component `axis` (0: x, 2: z) at a point x of an
// entry side, at time t (`Inflow::velocity_at`):
// u = U d (1 + a g(t - delay) cos(pi y / H)), y above the grid's floor, the
// delay a front's arrival from the most upwind corner plus its lean across
// the wind; the same flux at every instant, gusts carried downwind by
// advection.
float inflow_velocity(uint axis, vec3 x, float t) {
    float speed = pc.inflow_speed;
    float amplitude = pc.gust_amplitude;
    vec2 d = inflow_heading();
    float component = axis == 0u ? d.x : d.y;
    if (amplitude == 0.0) {
        return speed * component;
    }
    float magnitude = max(abs(speed), 1e-3);
    float lean = INFLOW_GUST_LEAN * (-d.y * x.x + d.x * x.z) / magnitude;
    vec3 size = vec3(pc.grid.cells) * pc.grid.cell_size;
    float x0 = d.x * speed < 0.0 ? pc.grid.origin.x + size.x : pc.grid.origin.x;
    float z0 = d.y * speed < 0.0 ? pc.grid.origin.z + size.z : pc.grid.origin.z;
    float sign_u = speed >= 0.0 ? 1.0 : -1.0;
    float arrival = sign_u * ((x.x - x0) * d.x + (x.z - z0) * d.y) / magnitude;
    float g = gust_signal(pc.gust_frequency, pc.gust_phases, t,
                          INFLOW_GUST_LEAN_SIGN * lean + arrival);
    float y = x.y - pc.grid.origin.y;
    return speed * (1.0 + amplitude * g * cos(0.5 * TAU * y / size.y)) * component;
}

uint cell_count() {
    return pc.grid.cells.x * pc.grid.cells.y * pc.grid.cells.z;
}

#endif
