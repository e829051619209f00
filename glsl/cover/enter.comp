#version 450
#extension GL_GOOGLE_include_directive : require
// The cover's tiles coming into its simulated square
// (`compute::CoverDynamics`): each of their blades starts where the tile
// pass showed it the frame before, at the angles and rates its last pose
// left (`FarPose`), so the paper's dynamics take over without a jolt; a
// blade the tile pass did not pose then starts where its torques balance
// in the wind at its rest tip (the quasi-static pose,
// glsl/grass/quasi_static.glsl), still. One dispatch a tile.

#include "wind_grid.glsl"
#include "blade_vertex.glsl"
#include "../grass/quasi_static.glsl"

layout(local_size_x = COVER_GROUP) in;

// CoverEnterPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    CoverEnterPush pc;
};

// The dynamics' blades and states (`GrassPass`), in its slot order.
layout(set = 0, binding = 0, std430) readonly buffer Blades { GrassBlade blades[]; };
layout(set = 0, binding = 1, std430) buffer States { GrassState states[]; };
layout(set = 0, binding = 2, std430) readonly buffer Wind { float wind_velocity[]; };
// The tile pass's last poses (glsl/cover/tiles.comp).
layout(set = 0, binding = 3, std430) readonly buffer FarPoses { FarPose far_poses[]; };
#define WIND_VELOCITY(i) wind_velocity[i]
#include "wind_sample.glsl"

void main() {
    if (gl_GlobalInvocationID.x >= pc.count) {
        return;
    }
    uint id = pc.first + gl_GlobalInvocationID.x;
    // far_tag 0: no last poses kept (a placeholder is bound).
    if (pc.far_tag != 0u) {
        FarPose last = far_poses[pc.far_first + gl_GlobalInvocationID.x];
        if (last.tile == pc.far_tag) {
            states[id] = GrassState(last.angle, last.velocity);
            return;
        }
    }
    GrassBlade b = blades[id];
    vec4 angle = quasi_static_angles(b, sample_wind(pc.grid, b.rest_tip));
    states[id] = GrassState(angle, vec4(0.0));
}
