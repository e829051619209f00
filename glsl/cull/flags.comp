#version 450
#extension GL_GOOGLE_include_directive : require
// Cull pass, 1 of 3: one invocation per blade tests the blade's current
// control points (glsl/common/cull.glsl) and, for a blade in view, its
// bounds against the previous frame's depth pyramid, for a caster the box
// its shadow can fall in (ours: a shadow that falls only where the depth
// hides every receiver darkens nothing seen), stores its flags, and each
// workgroup stores how many of its blades each pass draws, how many the
// distance thinning keeps, how many of those face the camera, and how
// many in view and how many casters the previous frame's depth hides.

#include "cull.glsl"
#include "depth_pyramid.glsl"

layout(local_size_x = CULL_GROUP) in;

// CullPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    CullPush pc;
};

// This batch's blades' control points (src/gpu/batches.rs).
layout(set = 0, binding = 1, std430) readonly buffer Vertices { BladeVertex vertices[]; };
layout(set = 0, binding = 2, std430) buffer Flags { uint flags[]; };
layout(set = 0, binding = 3, std430) buffer Groups { uvec4 group_counts[]; };
layout(set = 0, binding = 7, std430) buffer GroupsOccluded { uvec2 group_occluded[]; };
layout(set = 0, binding = 8, std430) readonly buffer Pyramid { float pyramid[]; };

shared uvec4 counts[CULL_GROUP];
shared uvec2 occluded_counts[CULL_GROUP];

// Whether the previous frame's depth hides the box `lo`-`hi` wholly: its
// nearest depth, seen as that frame saw, lies behind the farthest depth of
// every texel under its screen rectangle, so every fragment of what it
// holds would have failed that frame's depth test. The pyramid's level is
// the one where the rectangle spans at most 2 x 2 texels. A box reaching
// behind that frame's camera or out of its view is never hidden: that
// frame did not see what lay there. The previous frame's occluders may
// have moved since; what a blade shows for that one frame is the test's
// approximation (Jahrmann and Wimmer's, too).
uint box_occluded(vec3 lo, vec3 hi) {
    vec2 rect_lo = vec2(3.0e38), rect_hi = vec2(-3.0e38);
    float nearest = 3.0e38;
    uint in_front = 1u;
    for (int c = 0; c < 8; ++c) {
        vec3 corner = mix(lo, hi, vec3(bvec3((c & 1) != 0, (c & 2) != 0, (c & 4) != 0)));
        vec4 clip = pc.seen_from * vec4(corner, 1.0);
        in_front &= uint(clip.w > 1e-6 && clip.z >= 0.0);
        vec3 ndc = clip.xyz / max(clip.w, 1e-6);
        rect_lo = min(rect_lo, ndc.xy);
        rect_hi = max(rect_hi, ndc.xy);
        nearest = min(nearest, ndc.z);
    }
    uint on_screen = uint(all(greaterThanEqual(rect_lo, vec2(-1.0))) && all(lessThanEqual(rect_hi, vec2(1.0))));
    vec2 size = vec2(uvec2(pc.pyramid_width, pc.pyramid_height));
    vec2 a = clamp((rect_lo * 0.5 + 0.5) * size, vec2(0.0), size - 1.0);
    vec2 b = clamp((rect_hi * 0.5 + 0.5) * size, vec2(0.0), size - 1.0);
    float extent = max(b.x - a.x, b.y - a.y);
    uint level = min(uint(ceil(log2(max(extent, 1.0)))), pc.pyramid_levels - 1u);
    uvec3 at = pyramid_level(uvec2(pc.pyramid_width, pc.pyramid_height), level);
    uvec2 first = uvec2(a) >> level, last = min(uvec2(b) >> level, at.yz - 1u);
    float farthest = 0.0;
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            farthest = max(farthest, pyramid[at.x + y * at.y + x]);
        }
    }
    return pc.pyramid_holds & in_front & on_screen & uint(nearest > farthest);
}

void main() {
    uint in_batch = gl_GlobalInvocationID.x;
    uint blade = pc.first_blade + in_batch;
    uint i = gl_LocalInvocationID.x;
    uint f = 0u;
    if (blade < pc.blade_count) {
        BladeVertex v[4];
        for (int k = 0; k < 4; ++k) {
            v[k] = vertices[4u * in_batch + uint(k)];
        }
        vec3 lo, hi, swept_lo, swept_hi;
        bool swept;
        f = cull_flags(v, pc.shadows != 0u, pc.edge_on, lo, hi, swept_lo, swept_hi, swept);
        uint occluded = (f & CULL_IN_VIEW) & box_occluded(lo, hi);
        f = (f & ~(occluded * CULL_IN_VIEW)) | occluded * CULL_OCCLUDED;
        uint shadow_occluded = ((f & CULL_CASTER) >> 1) & uint(swept) & box_occluded(swept_lo, swept_hi);
        f = (f & ~(shadow_occluded * CULL_CASTER)) | shadow_occluded * CULL_SHADOW_OCCLUDED;
        flags[blade] = f;
    }
    counts[i] = uvec4(f & CULL_IN_VIEW, (f & CULL_CASTER) >> 1, (f & CULL_KEPT) >> 2, (f & CULL_FACING) >> 3);
    occluded_counts[i] = uvec2((f & CULL_OCCLUDED) >> 4, (f & CULL_SHADOW_OCCLUDED) >> 5);
    barrier();
    for (uint half_ = CULL_GROUP / 2u; half_ > 0u; half_ >>= 1u) {
        if (i < half_) {
            counts[i] += counts[i + half_];
            occluded_counts[i] += occluded_counts[i + half_];
        }
        barrier();
    }
    if (i == 0u) {
        uint group = pc.first_blade / CULL_GROUP + gl_WorkGroupID.x;
        group_counts[group] = counts[0];
        group_occluded[group] = occluded_counts[0];
    }
}
