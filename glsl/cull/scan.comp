#version 450
#extension GL_GOOGLE_include_directive : require
// Cull pass, 2 of 3: one workgroup turns the per-workgroup counts into
// each workgroup's first slot in the two lists (an exclusive prefix sum, in
// blade order, so the lists and the frames are the same every run) and
// writes both passes' indexed indirect draws.

#include "cull.glsl"

layout(local_size_x = 256) in;

// CullPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    CullPush pc;
};

layout(set = 0, binding = 3, std430) buffer Groups { uvec4 group_counts[]; };
// Two VkDrawIndexedIndirectCommand (index count, instance count, first
// index, vertex offset, first instance): the colour pass's, the shadow
// pass's; then the blades tested, those the distance thinning kept, and
// those of them not seen edge-on from the camera, and the blades in view
// the previous frame's depth hides, and the casters whose shadow it hides.
layout(set = 0, binding = 4, std430) buffer Draws { uint draws[]; };
layout(set = 0, binding = 7, std430) readonly buffer GroupsOccluded { uvec2 group_occluded[]; };

shared uvec4 sums[256];
shared uint occluded, casters_occluded;

void main() {
    uint i = gl_LocalInvocationID.x;
    uint groups = pc.flag_groups;
    uint chunk = (groups + 255u) / 256u;
    uint first = min(i * chunk, groups), last = min(first + chunk, groups);
    uvec4 sum = uvec4(0u);
    uvec2 hidden = uvec2(0u);
    for (uint g = first; g < last; ++g) {
        sum += group_counts[g];
        hidden += group_occluded[g];
    }
    if (i == 0u) {
        occluded = 0u;
        casters_occluded = 0u;
    }
    barrier();
    atomicAdd(occluded, hidden.x);
    atomicAdd(casters_occluded, hidden.y);
    // Inclusive scan of the chunks' sums (Hillis-Steele).
    sums[i] = sum;
    barrier();
    for (uint offset = 1u; offset < 256u; offset <<= 1u) {
        uvec4 add = i >= offset ? sums[i - offset] : uvec4(0u);
        barrier();
        sums[i] += add;
        barrier();
    }
    uvec4 running = sums[i] - sum;
    for (uint g = first; g < last; ++g) {
        uvec4 count = group_counts[g];
        group_counts[g] = running;
        running += count;
    }
    if (i == 255u) {
        uvec4 total = sums[255];
        draws[0] = 4u * total.x;   // colour: four control points per blade
        draws[1] = 1u;
        draws[2] = 0u;
        draws[3] = 0u;
        draws[4] = 0u;
        draws[5] = 4u * total.y;   // shadow
        draws[6] = 1u;
        draws[7] = 0u;
        draws[8] = 0u;
        draws[9] = 0u;
        draws[10] = pc.blade_count;
        draws[11] = total.z;       // kept by the distance thinning
        draws[12] = total.w;       // of those, not edge-on to the camera
        draws[13] = occluded;      // in view, hidden by the previous frame's depth
        draws[14] = casters_occluded; // casters whose shadow it hides
    }
}
