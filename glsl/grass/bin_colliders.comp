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

layout(local_size_x = 64) in;

#include "collider.glsl"

layout(push_constant, std430) uniform Push {
    vec4 grid;     // xy: the grid's corner (x, z; m), z: cells per metre, w: time at the step's end (s)
    uvec4 cells;   // x: columns (along x), y: rows (along z), z: colliders
    vec4 reach;    // x: the longest blade's reach with a margin (m), y, z: the roots' lowest and highest y (m)
} pc;

layout(set = 0, binding = 0, std430) readonly buffer Colliders { Collider colliders[]; };
// Written only; not declared writeonly because naga does not take it.
layout(set = 0, binding = 1, std430) buffer States { ColliderState states[]; };
// Four words per cell (bit c: collider c), row after row.
layout(set = 0, binding = 2, std430) buffer Bins { uint bins[]; };

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= pc.cells.z) {
        return;
    }
    ColliderState st = collider_at(colliders[c], pc.grid.w);
    states[c] = st;
    float grow = st.a_radius.w + pc.reach.x;
    vec3 low = min(st.a_radius.xyz, st.b.xyz) - vec3(grow);
    vec3 high = max(st.a_radius.xyz, st.b.xyz) + vec3(grow);
    if (high.y < pc.reach.y || low.y > pc.reach.z) {
        return;
    }
    // Cells as the step kernel finds a root's (`bin_of` in step.glsl),
    // clamped in float first so that a collider far off never overflows.
    vec2 columns_rows = vec2(pc.cells.xy);
    vec2 first = clamp(floor((low.xz - pc.grid.xy) * pc.grid.z), vec2(-1.0), columns_rows);
    vec2 last = clamp(floor((high.xz - pc.grid.xy) * pc.grid.z), vec2(-1.0), columns_rows);
    if (any(lessThan(last, vec2(0.0))) || any(greaterThanEqual(first, columns_rows))) {
        return;
    }
    uvec2 from = uvec2(max(first, vec2(0.0)));
    uvec2 to = uvec2(min(last, columns_rows - 1.0));
    uint word = c >> 5;
    uint bit = 1u << (c & 31u);
    for (uint row = from.y; row <= to.y; ++row) {
        for (uint column = from.x; column <= to.x; ++column) {
            atomicOr(bins[4u * (row * pc.cells.x + column) + word], bit);
        }
    }
}
