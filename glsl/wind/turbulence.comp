#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 7, with turbulence (`WindField::add_turbulence`,
// src/model/turbulence.rs): every free and buried face gains the sum of the
// Fourier modes at the step's end, and keeps what it gained in `added` for
// the next step's forces kernel to take off. The modes are written before
// each step with their phases then.
#include "wind_kernel.glsl"

// TurbulenceMode: src/interface/defs.rs.
layout(set = 0, binding = 12, std430) readonly buffer Modes { TurbulenceMode modes[]; };

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.grid.faces) {
        return;
    }
    uint kind = face_kind[id];
    if (kind != FACE_FREE && kind != FACE_BURIED) {
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    // From the grid's corner, where the phases are taken.
    vec3 offset = vec3(0.5);
    offset[axis] = 0.0;
    vec3 x = (vec3(f) + offset) * pc.grid.cell_size.xyz;
    float u = 0.0;
    for (uint n = 0u; n < uint(modes.length()); ++n) {
        vec4 k = modes[n].wavenumber_phase;
        u += modes[n].amplitude[axis] * cos(k.x * x.x + k.y * x.y + k.z * x.z + k.w);
    }
    vel[id] += u;
    turbulence_added[id] = u;
}
