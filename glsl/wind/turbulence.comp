#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 7, with turbulence (`WindField::add_turbulence`,
// src/model/turbulence.rs): every free and inflow face gains the sum of
// the Fourier modes at the step's end, and keeps what it gained in
// `turbulence_added` for the next step's forces kernel to take off (an
// inflow face is set anew there). The modes are written before each step
// with their phases then. On a grid with solid cells it runs before the
// projection, which turns the modes' flow around the solids, on the
// advected copy B the projection reads (`INTO_COPY` 1;
// `WindPass::record_step`); a buried face then takes the air above's
// value, turbulence and all (glsl/wind/under_ground.comp).
#include "wind_kernel.glsl"
#include "turbulence.glsl"

// TurbulenceMode: src/interface/defs.rs.
layout(set = 0, binding = 12, std430) readonly buffer Modes { TurbulenceMode modes[]; };
// The velocity copy the field is added to: 0 the state A (after the
// projection, or a window's move), 1 the advected B (before it).
layout(constant_id = 0) const uint INTO_COPY = 0u;
// The modes' mirrored axes, the same for every mode
// (`TurbulenceField::mirrored`): read from each mode (FROM_MODES 7), or
// MIRRORED, a constant the pipeline is made with (FROM_MODES 0), which
// leaves out the code of the axes not mirrored. That matters on lavapipe,
// which runs both sides of every test: each mode took eight sines and
// cosines there whatever it was mirrored across.
layout(constant_id = 1) const uint FROM_MODES = 7u;
layout(constant_id = 2) const uint MIRRORED = 0u;

uint mirrored_of(TurbulenceMode m) {
    return (m.mirrored & FROM_MODES) | MIRRORED;
}


void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.grid.faces) {
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    // A face that gains nothing keeps nothing to take off (after a
    // window's move its index may have held a free face's share).
    if (face_kind[id] == FACE_BURIED) {
        turbulence_added[id] = 0.0;
        return;
    }
    // Walls gain nothing, but for those on the sides across an axis the
    // modes are not mirrored across, before a cell of air (a moving
    // window's sides along the wind; `add_turbulence_now`): the next
    // step's forces wall them again.
    if (face_kind[id] == FACE_WALL) {
        uvec3 n = pc.grid.cells.xyz;
        uvec3 c = f;
        c[axis] = min(c[axis], n[axis] - 1u);
        bool open_side = axis != 1u && (f[axis] == 0u || f[axis] == n[axis])
            && (mirrored_of(modes[0]) & (1u << axis)) == 0u
            && solid[cell_index(pc.grid, c)] == 0u;
        if (!open_side) {
            turbulence_added[id] = 0.0;
            return;
        }
    }
    // The face's half-cell point (`TurbulenceField::face_point`): 2 f
    // along its axis, 2 f + 1 across.
    uvec3 q = 2u * f + 1u;
    q[axis] -= 1u;
    vec3 x = vec3(q) * 0.5 * pc.grid.cell_size.xyz;
    float u = 0.0;
    for (uint n = 0u; n < uint(modes.length()); ++n) {
        TurbulenceMode m = modes[n];
        u += turbulence_component_mirrored(m, mirrored_of(m), axis, x);
    }
    vel[INTO_COPY * pc.grid.faces + id] += u;
    turbulence_added[id] = u;
}
