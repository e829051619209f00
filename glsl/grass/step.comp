#version 450
#extension GL_GOOGLE_include_directive : require
// The grass step (paper section 4): one invocation per blade samples the wind
// at its tip, advances swinging, bending and twisting, and writes the four
// deformed control points and width vectors straight into the vertex buffer
// the blade pipeline draws. Mirrors `GrassField::step` in src/sim/grass.rs.

layout(local_size_x = 64) in;

#include "wind_grid.glsl"
#include "blade_vertex.glsl"
#include "dynamics.glsl"

layout(push_constant, std430) uniform Push {
    WindGridParams grid;
    uvec4 control;   // x: blades, y: substeps, z: offset (floats) of the wind velocity copy to sample
    vec4 step;       // x: simulation step dt (s), y: substep h = dt / substeps (s)
} pc;

layout(set = 0, binding = 0, std430) readonly buffer Blades { GrassBlade blades[]; };
layout(set = 0, binding = 1, std430) buffer States { GrassState states[]; };
struct Vertex {
    vec4 position;
    vec4 width;
};
// Written only; not declared writeonly because naga does not take it.
layout(set = 0, binding = 2, std430) buffer Vertices { Vertex vertices[]; };
layout(set = 0, binding = 3, std430) readonly buffer Wind { float wind_velocity[]; };
// Blade-steps that ended at an angle cap (`CapCounts` in src/sim/grass.rs):
// [0] any motion, [1 + m] motion m (swing, bend A, bend B, twist).
layout(set = 0, binding = 4, std430) buffer Caps { uint caps[]; };

#define WIND_VELOCITY(i) wind_velocity[pc.control.z + (i)]
#include "wind_sample.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.control.x) {
        return;
    }
    GrassBlade b = blades[id];
    GrassState s = states[id];
    // The wind only at the tip (paper section 4).
    vec3 tip = blade_pose(b, s.angle).points[3];
    blade_step(b, s, sample_wind(pc.grid, tip), pc.step.y, pc.control.y);
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

    // Width vectors: the twisted E_w_local of the edge ending at each point
    // (the root takes the root edge's); w: the tip edge's angle from rest.
    Pose p = blade_pose(b, s.angle);
    vec3 rest_tip = normalize_or(rest_point(b, 3) - rest_point(b, 2), UP);
    float displacement = atan(length(cross(rest_tip, p.e[2])), dot(rest_tip, p.e[2]));
    for (int i = 0; i < BLADE_CONTROL_POINTS; ++i) {
        int edge = max(i, 1) - 1;
        vertices[4u * id + uint(i)] = Vertex(vec4(p.points[i], b.rest[i].w),
                                             vec4(p.w_local[edge] * b.width.w, displacement));
    }
}
