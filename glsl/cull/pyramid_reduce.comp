#version 450
#extension GL_GOOGLE_include_directive : require
// Depth pyramid, one level above level 0: one invocation per texel stores
// the farthest of the (up to) 2 x 2 texels below it. The levels' places
// come as push constants, not as a level number, so no branch depends on
// a uniform alone (lavapipe compiles a variant per value of such uniforms;
// glsl/common/cull.glsl).

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant, std430) uniform Push {
    uvec4 below;   // x: offset in the buffer, y, z: size
    uvec4 level;   // the same for the level written
} pc;

layout(set = 0, binding = 1, std430) buffer Pyramid { float pyramid[]; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x < pc.level.y && p.y < pc.level.z) {
        uvec2 last = pc.below.yz - 1u;
        uvec2 a = min(2u * p, last), b = min(2u * p + 1u, last);
        uint row_a = pc.below.x + a.y * pc.below.y, row_b = pc.below.x + b.y * pc.below.y;
        float farthest = max(max(pyramid[row_a + a.x], pyramid[row_a + b.x]),
                             max(pyramid[row_b + a.x], pyramid[row_b + b.x]));
        pyramid[pc.level.x + p.y * pc.level.y + p.x] = farthest;
    }
}
