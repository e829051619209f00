#version 450
#extension GL_GOOGLE_include_directive : require
// Cull pass, 3 of 3: each surviving blade writes its four control points'
// indices into the lists the passes draw, at its workgroup's first slot
// plus its rank among the workgroup's survivors: the lists keep blade order.

#include "cull.glsl"

layout(local_size_x = CULL_GROUP) in;

// CullPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    CullPush pc;
};

layout(set = 0, binding = 2, std430) buffer Flags { uint flags[]; };
layout(set = 0, binding = 3, std430) buffer Groups { uvec4 group_counts[]; };
layout(set = 0, binding = 5, std430) buffer ColorList { uvec4 color_list[]; };
layout(set = 0, binding = 6, std430) buffer ShadowList { uvec4 shadow_list[]; };

shared uvec2 ranks[CULL_GROUP];

void main() {
    uint blade = gl_GlobalInvocationID.x;
    uint i = gl_LocalInvocationID.x;
    uint f = blade < pc.blade_count ? flags[blade] : 0u;
    uvec2 mine = uvec2(f & CULL_IN_VIEW, (f & CULL_CASTER) >> 1);
    ranks[i] = mine;
    barrier();
    for (uint offset = 1u; offset < CULL_GROUP; offset <<= 1u) {
        uvec2 add = i >= offset ? ranks[i - offset] : uvec2(0u);
        barrier();
        ranks[i] += add;
        barrier();
    }
    uvec2 slot = group_counts[gl_WorkGroupID.x].xy + ranks[i] - mine;
    uvec4 indices = 4u * blade + uvec4(0u, 1u, 2u, 3u);
    if (mine.x != 0u) {
        color_list[slot.x] = indices;
    }
    if (mine.y != 0u) {
        shadow_list[slot.y] = indices;
    }
}
