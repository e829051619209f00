#version 450
#extension GL_GOOGLE_include_directive : require
// The wind window moved by whole cells (`WindField::shift_window`,
// src/model/wind/window.rs), in two phases with a barrier between:
// 0 gathers, into copy B, what the face at each face's world position held
// (the turbulence the last step added taken off; a new face, or one whose
// source was a wall, takes the inflow's mean velocity), and into the
// divergence buffer the canopy of the cell there; 1 copies both back,
// zero on the faces that are walls now, and clears the pressure (its
// three copies: the multigrid's start reads the last two steps'). Over
// terrain the moved grid's face kinds are written between the phases
// (`WindPass::record_shift`): phase 0 reads the kinds the air had, phase
// 1 those it has. The turbulence kernel then adds the field where the
// faces now are.
#include "wind_grid.glsl"

layout(local_size_x = WIND_GROUP) in;

// WindShiftPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    WindShiftPush pc;
};

// The wind kernels' set (glsl/wind/wind_kernel.glsl): copy A = [0, F) the
// state, copy B = [F, 2F) free between steps.
layout(set = 0, binding = 0, std430) buffer Velocity { float vel[]; };
layout(set = 0, binding = 1, std430) readonly buffer Faces { uint face_kind[]; };
// Two copies for the Jacobi ping-pong.
layout(set = 0, binding = 3, std430) buffer Pressure { float pressure[]; };
// The divergence, which every step recomputes: scratch for the canopy
// between the phases, read as the counts it holds.
layout(set = 0, binding = 4, std430) buffer Divergence { uint canopy_moved[]; };
layout(set = 0, binding = 9, std430) buffer Canopy { uint canopy[]; };
layout(set = 0, binding = 11, std430) readonly buffer TurbulenceAdded { float turbulence_added[]; };

// The face (or cell, `dims` the cells) at `f` moved by the shift, if the
// grid had it.
bool moved(uvec3 f, uvec3 dims, out uvec3 source) {
    ivec3 s = ivec3(f) + ivec3(pc.shift.x, 0, pc.shift.y);
    source = uvec3(s);
    return s.x >= 0 && s.z >= 0 && s.x < int(dims.x) && s.z < int(dims.z);
}

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint faces = pc.grid.faces;
    uvec3 n = pc.grid.cells.xyz;
    uint cells = n.x * n.y * n.z;
    if (pc.phase == 1u) {
        if (id < faces) {
            vel[id] = face_kind[id] == FACE_WALL ? 0.0 : vel[faces + id];
        }
        if (id < cells) {
            canopy[id] = canopy_moved[id];
            pressure[id] = 0.0;
            pressure[cells + id] = 0.0;
            pressure[2u * cells + id] = 0.0;
        }
        return;
    }
    if (id < faces) {
        uint axis;
        uvec3 f;
        face_of(pc.grid, id, axis, f);
        uvec3 s;
        uint src = moved(f, face_dims(pc.grid, axis), s) ? face_index(pc.grid, axis, s) : faces;
        // Without turbulence its buffer holds one word (zero): read only
        // where it was added.
        bool kept = src < faces && face_kind[src] != FACE_WALL;
        vel[faces + id] = kept ? vel[src] - (src < uint(turbulence_added.length()) ? turbulence_added[src] : 0.0)
                               : pc.fill[axis];
    }
    if (id < cells) {
        uvec3 c = uvec3(id % n.x, (id / n.x) % n.y, id / (n.x * n.y));
        uvec3 s;
        canopy_moved[id] = moved(c, n, s) ? canopy[cell_index(pc.grid, s)] : 0u;
    }
}
