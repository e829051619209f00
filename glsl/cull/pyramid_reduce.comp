#version 450
#extension GL_GOOGLE_include_directive : require
// Depth pyramid, one level above level 0: one invocation per texel stores
// the farthest of the (up to) 2 x 2 texels below it. The levels' places
// come as push constants, not as a level number, so no branch depends on
// a uniform alone (lavapipe compiles a variant per value of such uniforms;
// glsl/common/cull.glsl).

#include "interface.glsl"

layout(local_size_x = PYRAMID_TILE, local_size_y = PYRAMID_TILE) in;

// PyramidPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    PyramidPush pc;
};

layout(set = 0, binding = 1, std430) buffer Pyramid { float pyramid[]; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x < pc.level.width && p.y < pc.level.height) {
        uvec2 last = uvec2(pc.below.width, pc.below.height) - 1u;
        uvec2 a = min(2u * p, last), b = min(2u * p + 1u, last);
        uint row_a = pc.below.offset + a.y * pc.below.width, row_b = pc.below.offset + b.y * pc.below.width;
        float farthest = max(max(pyramid[row_a + a.x], pyramid[row_a + b.x]),
                             max(pyramid[row_b + a.x], pyramid[row_b + b.x]));
        pyramid[pc.level.offset + p.y * pc.level.width + p.x] = farthest;
    }
}
