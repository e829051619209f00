#version 450
#extension GL_GOOGLE_include_directive : require
// Cull pass, 1 of 3: one invocation per blade tests the blade's current
// control points (glsl/common/cull.glsl), stores its flags, and each
// workgroup stores how many of its blades each pass draws, how many the
// distance thinning keeps, and how many of those face the camera.

#include "cull.glsl"

layout(local_size_x = 256) in;

layout(push_constant, std430) uniform Push {
    uvec4 control;   // x: blades, y: workgroups of the flag kernel, z: 1 = shadows on,
                     // w: this batch's first blade (a multiple of CULL_GROUP)
    vec4 tests;      // x: edge_on, the orientation test's cosine (1 = off)
} pc;

// This batch's blades' control points (src/gpu/batches.rs).
layout(set = 0, binding = 1, std430) readonly buffer Vertices { Vertex vertices[]; };
layout(set = 0, binding = 2, std430) buffer Flags { uint flags[]; };
layout(set = 0, binding = 3, std430) buffer Groups { uvec4 group_counts[]; };

shared uvec4 counts[CULL_GROUP];

void main() {
    uint in_batch = gl_GlobalInvocationID.x;
    uint blade = pc.control.w + in_batch;
    uint i = gl_LocalInvocationID.x;
    uint f = 0u;
    if (blade < pc.control.x) {
        Vertex v[4];
        for (int k = 0; k < 4; ++k) {
            v[k] = vertices[4u * in_batch + uint(k)];
        }
        f = cull_flags(v, pc.control.z != 0u, pc.tests.x);
        flags[blade] = f;
    }
    counts[i] = uvec4(f & CULL_IN_VIEW, (f & CULL_CASTER) >> 1, (f & CULL_KEPT) >> 2, (f & CULL_FACING) >> 3);
    barrier();
    for (uint half_ = CULL_GROUP / 2u; half_ > 0u; half_ >>= 1u) {
        if (i < half_) {
            counts[i] += counts[i + half_];
        }
        barrier();
    }
    if (i == 0u) {
        group_counts[pc.control.w / CULL_GROUP + gl_WorkGroupID.x] = counts[0];
    }
}
