#version 450
#extension GL_GOOGLE_include_directive : require
// Collider binning (ours; docs/physics.md, "Colliders"), before each grass
// step: one invocation per collider evaluates it once at the step's end
// (`collider_at`) for every blade to read, and marks its bit in each cell of
// a coarse grid over the field's roots that its box, grown by its radius and
// the longest blade's reach, covers. A blade then tests only the colliders
// of its root's cell, in scene order: a superset of its near colliders on
// the CPU (`contact::near_blade`), as a collider left out cannot reach it.
// The bins are cleared before (a fill); bits are or-ed, the same in any order.

#include "collider.glsl"

layout(local_size_x = GRASS_GROUP) in;

// BinPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    BinPush pc;
};

layout(set = 0, binding = 0, std430) readonly buffer Colliders { GpuCollider colliders[]; };
// Written only; not declared writeonly because naga does not take it.
layout(set = 0, binding = 1, std430) buffer States { GpuColliderState states[]; };
// Four words per cell (bit c: collider c), row after row.
layout(set = 0, binding = 2, std430) buffer Bins { uint bins[]; };

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= pc.collider_count) {
        return;
    }
    GpuColliderState st = collider_at(colliders[c], pc.end_time);
    states[c] = st;
    float grow = st.radius + pc.reach;
    vec3 low = min(st.a, st.b) - vec3(grow);
    vec3 high = max(st.a, st.b) + vec3(grow);
    if (high.y < pc.root_low || low.y > pc.root_high) {
        return;
    }
    // Cells as the step kernel finds a root's (`bin_of` in step.glsl),
    // clamped in float first so that a collider far off never overflows.
    vec2 columns_rows = vec2(uvec2(pc.columns, pc.rows));
    vec2 first = clamp(floor((low.xz - pc.corner) * pc.per_metre), vec2(-1.0), columns_rows);
    vec2 last = clamp(floor((high.xz - pc.corner) * pc.per_metre), vec2(-1.0), columns_rows);
    if (any(lessThan(last, vec2(0.0))) || any(greaterThanEqual(first, columns_rows))) {
        return;
    }
    uvec2 from = uvec2(max(first, vec2(0.0)));
    uvec2 to = uvec2(min(last, columns_rows - 1.0));
    uint word = c >> 5;
    uint bit = 1u << (c & 31u);
    for (uint row = from.y; row <= to.y; ++row) {
        for (uint column = from.x; column <= to.x; ++column) {
            atomicOr(bins[4u * (row * pc.columns + column) + word], bit);
        }
    }
}
