// Depth pyramid, level 0: one invocation per pixel of the colour pass's
// depth stores the farthest of its samples (cleared depth is 1, the far
// plane): whatever any sample of the pixel showed, it was no farther.

#extension GL_EXT_samplerless_texture_functions : require

#include "interface.glsl"

layout(local_size_x = PYRAMID_TILE, local_size_y = PYRAMID_TILE) in;

// PyramidPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    PyramidPush pc;
};

#ifdef PYRAMID_MULTISAMPLED
layout(set = 0, binding = 0) uniform texture2DMS depth_image;
#else
layout(set = 0, binding = 0) uniform texture2D depth_image;
#endif
layout(set = 0, binding = 1, std430) buffer Pyramid { float pyramid[]; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x < pc.level.width && p.y < pc.level.height) {
#ifdef PYRAMID_MULTISAMPLED
        int samples = textureSamples(depth_image);
        float farthest = 0.0;
        for (int s = 0; s < samples; ++s) {
            farthest = max(farthest, texelFetch(depth_image, ivec2(p), s).r);
        }
#else
        float farthest = texelFetch(depth_image, ivec2(p), 0).r;
#endif
        pyramid[pc.level.offset + p.y * pc.level.width + p.x] = farthest;
    }
}
