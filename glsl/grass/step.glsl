// The grass step (paper section 4), in two kernels: step.comp, one
// invocation per blade, and step_touching.comp (GRASS_TOUCHING defined),
// one per blade of the list step.comp made of those near a collider or
// pressed. Each samples the wind at its blade's tip, advances swinging,
// bending and twisting, and writes the four deformed control points and
// width vectors straight into the vertex buffer the blade pipeline draws.
// Mirrors `GrassField::step` in src/model/grass.rs.
//
// Why two: a SIMD device that runs every branch masked (lavapipe: 8 blades
// in the lanes of one register) pays for the contact code in every blade
// of a group, touching or not; the blades that touch nothing run a kernel
// without it.
#ifndef MEADOW_GRASS_STEP_GLSL
#define MEADOW_GRASS_STEP_GLSL

#include "wind_grid.glsl"
#include "blade_vertex.glsl"
#include "dynamics.glsl"
#include "collider.glsl"

layout(local_size_x = GRASS_GROUP) in;

// The colliders at the step's end, evaluated once by the binning pass
// (bin_colliders.comp); contact.glsl reads them, so they come before it.
layout(set = 0, binding = 7, std430) readonly buffer ColliderStates { GpuColliderState collider_states[]; };
#define COLLIDER_STATE(c) collider_states[c]
#include "contact.glsl"

// GrassPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    GrassPush pc;
};

layout(set = 0, binding = 0, std430) readonly buffer Blades { GrassBlade blades[]; };
layout(set = 0, binding = 1, std430) buffer States { GrassState states[]; };
// Written only; not declared writeonly because naga does not take it.
layout(set = 0, binding = 2, std430) buffer Vertices { BladeVertex vertices[]; };
layout(set = 0, binding = 3, std430) readonly buffer Wind { float wind_velocity[]; };
// Blade-steps that ended at an angle cap (`CapCounts` in src/model/grass.rs):
// [0] any motion, [1 + m] motion m (swing, bend A, bend B, twist).
layout(set = 0, binding = 4, std430) buffer Caps { uint caps[]; };
// The frontal area per wind cell in counts of pc.canopy_unit m^2 (two-way
// coupling; `deposit` in src/model/canopy.rs), which the wind cleared.
layout(set = 0, binding = 5, std430) buffer Canopy { uint canopy[]; };
// Each blade's pressed state (`Press` in src/model/contact.rs); like the
// colliders' states, bins and lists below, a placeholder the kernels never
// touch when made without colliders.
layout(set = 0, binding = 6, std430) buffer Presses { Press presses[]; };
// Four words per cell, one bit per collider (bin_colliders.comp).
layout(set = 0, binding = 8, std430) readonly buffer ColliderBins { uvec4 collider_bins[]; };
// The blades of this batch near a collider or pressed, which step.comp
// leaves to step_touching.comp: [0..3) the indirect dispatch's workgroups,
// [3] how many, then their slots in the batch, in no set order (each
// blade's step is its own; the sums it adds are integers).
layout(set = 0, binding = 9, std430) buffer Touching { uint touching[]; };
// Slot id steps the blade whose control points go to vertex_slot[id]: in
// place order with colliders (src/compute/place_order.rs), else the
// blade's own.
layout(set = 0, binding = 10, std430) readonly buffer VertexSlots { uint vertex_slot[]; };

// The bin of a root: the same arithmetic as bin_colliders.comp's cells.
uint bin_of(vec3 root) {
    vec2 cell = floor((root.xz - pc.bin_corner) * pc.bin_per_metre);
    uvec2 at = uvec2(clamp(cell, vec2(0.0), vec2(uvec2(pc.bin_columns, pc.bin_rows)) - 1.0));
    return at.y * pc.bin_columns + at.x;
}

#define WIND_VELOCITY(i) wind_velocity[pc.wind_offset + (i)]
#include "wind_sample.glsl"
#include "turbulence.glsl"

// The turbulence's modes finer than the wind grid as the wind step left
// them (`TurbulenceField::subgrid_records`; pc.subgrid_modes of them), or
// a placeholder never read.
layout(set = 0, binding = 11, std430) readonly buffer SubgridModes { TurbulenceMode subgrid_modes[]; };

// The wind the tip at `tip` feels (`WindField::felt`): the grid's, and the
// modes finer than it summed there.
vec3 felt_at(vec3 tip) {
    vec3 felt = sample_wind(pc.grid, tip);
    vec3 x = tip - pc.grid.origin.xyz;
    for (uint n = 0u; n < pc.subgrid_modes; ++n) {
        felt += turbulence_velocity(subgrid_modes[n], x);
    }
    return felt;
}

// Two-way coupling (`deposit` in src/model/canopy.rs): each edge's plate,
// projected across the wind the blade felt, added to the cell its midpoint
// lies in, in whole counts. Integer sums: the same in any order.
void lay_frontal_area(GrassBlade b, Pose p, vec3 wind) {
    float speed = length(wind);
    if (speed <= 1e-6) {
        return;
    }
    vec3 along = wind / speed;
    for (int i = 0; i < 3; ++i) {
        vec3 n = cross(p.w_local[i], p.e[i]);
        float n_len = length(n);
        float facing = n_len > 1e-12 ? abs(dot(n, along) / n_len) : 0.0;
        float area = length(rest_point(b, i + 1) - rest_point(b, i)) * 2.0 * b.half_width * facing;
        vec3 mid = (p.points[i] + p.points[i + 1]) * 0.5;
        vec3 g = floor((mid - pc.grid.origin.xyz) / pc.grid.cell_size.xyz);
        if (all(greaterThanEqual(g, vec3(0.0))) && all(lessThan(g, vec3(pc.grid.cells.xyz)))) {
            atomicAdd(canopy[cell_index(pc.grid, uvec3(g))], uint(area / pc.canopy_unit + 0.5));
        }
    }
}

// This blade's own near colliders (`contact::near_blade`), as bits in
// scene order: those of its root's bin within its reach.
uvec4 near_colliders(GrassBlade b) {
    uvec4 near = uvec4(0u);
    if (pc.collider_count > 0u) {
        vec3 root = b.rest_root;
        float reach = blade_reach(b);
        uvec4 binned = collider_bins[bin_of(root)];
        for (uint word = 0u; word < 4u; ++word) {
            for (uint bits = binned[word]; bits != 0u; bits &= bits - 1u) {
                uint c = word * 32u + uint(findLSB(bits));
                if (collider_distance(collider_states[c], root).x < reach) {
                    near[word] |= 1u << (c & 31u);
                }
            }
        }
    }
    return near;
}

// The step's end for the blade of slot `id`: its state, the cap counters,
// its frontal area (two-way coupling) and its control points.
void write_blade(uint id, GrassBlade b, GrassState s, float pressed, vec3 felt) {
    states[id] = s;
    bool capped = false;
    for (int m = 0; m < 4; ++m) {
        if (abs(s.angle[m]) >= MAX_ANGLE) {
            atomicAdd(caps[1 + m], 1u);
            capped = true;
        }
    }
    if (capped) {
        atomicAdd(caps[0], 1u);
    }

    Pose p = blade_pose(b, s.angle, pressed);
    if (pc.lay_canopy != 0u) {
        lay_frontal_area(b, p, guard_wind(felt));
    }

    // Width vectors: the twisted E_w_local of the edge ending at each point
    // (the root takes the root edge's); w: the tip edge's angle from rest.
    vec3 rest_tip = normalize_or(rest_point(b, 3) - rest_point(b, 2), UP);
    float displacement = atan(length(cross(rest_tip, p.e[2])), dot(rest_tip, p.e[2]));
    uint at = vertex_slot[id];
    for (int i = 0; i < BLADE_CONTROL_POINTS; ++i) {
        int edge = max(i, 1) - 1;
        vertices[4u * at + uint(i)] = BladeVertex(p.points[i], b.blade_rand,
                                             p.w_local[edge] * b.half_width, displacement);
    }
}

#ifndef GRASS_TOUCHING

// Every blade: one near a collider or pressed (pressed states live only in
// a pass made with colliders) goes on the list; the others take the
// paper's step, without the contact.
void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.blade_count) {
        return;
    }
    GrassBlade b = blades[id];
    if (pc.pressed_states != 0u) {
        Press press = presses[id];
        bool pressed = press_next(press, pc.dt, pc.press_decay) != 0.0;
        if (pressed || any(notEqual(near_colliders(b), uvec4(0u)))) {
            uint entry = atomicAdd(touching[3], 1u);
            touching[TOUCHING_HEADER + entry] = id;
            atomicMax(touching[0], entry / GRASS_GROUP + 1u);
            return;
        }
        if (press.pressed != 0.0) {
            // Decayed to nothing this step (`Press::next`).
            presses[id] = Press(0.0, 0.0);
        }
    }
    GrassState s = states[id];
    // The wind only at the tip (paper section 4), as the last step left it.
    vec3 tip = blade_pose(b, s.angle, 0.0).points[3];
    vec3 felt = felt_at(tip);
    blade_step(b, s, felt, pc.substep, pc.substeps, 0.0, uvec4(0u));
    write_blade(id, b, s, 0.0, felt);
}

#else

// The listed blades, with the contact.
void main() {
    if (gl_GlobalInvocationID.x >= touching[3]) {
        return;
    }
    uint id = touching[TOUCHING_HEADER + gl_GlobalInvocationID.x];
    GrassBlade b = blades[id];
    uvec4 near = near_colliders(b);
    GrassState s = states[id];
    Press press = presses[id];
    // The wind only at the tip (paper section 4), as the last step left it.
    vec3 tip = blade_pose(b, s.angle, press.pressed).points[3];
    vec3 felt = felt_at(tip);
    float pressed = press_next(press, pc.dt, pc.press_decay);
    bool touched = blade_step(b, s, felt, pc.substep, pc.substeps, pressed, near);
    presses[id] = Press(pressed, touched ? 1.0 : 0.0);
    write_blade(id, b, s, pressed, felt);
}

#endif
#endif
