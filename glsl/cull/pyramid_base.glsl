// Depth pyramid, level 0: one invocation per pixel of the colour pass's
// depth stores the farthest of its samples (cleared depth is 1, the far
// plane): whatever any sample of the pixel showed, it was no farther.

#extension GL_EXT_samplerless_texture_functions : require

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant, std430) uniform Push {
    uvec4 below;   // read by the levels above only
    uvec4 level;   // x: offset in the buffer (0), y, z: the depth image's size
} pc;

#ifdef PYRAMID_MULTISAMPLED
layout(set = 0, binding = 0) uniform texture2DMS depth_image;
#else
layout(set = 0, binding = 0) uniform texture2D depth_image;
#endif
layout(set = 0, binding = 1, std430) buffer Pyramid { float pyramid[]; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x < pc.level.y && p.y < pc.level.z) {
#ifdef PYRAMID_MULTISAMPLED
        int samples = textureSamples(depth_image);
        float farthest = 0.0;
        for (int s = 0; s < samples; ++s) {
            farthest = max(farthest, texelFetch(depth_image, ivec2(p), s).r);
        }
#else
        float farthest = texelFetch(depth_image, ivec2(p), 0).r;
#endif
        pyramid[pc.level.x + p.y * pc.level.y + p.x] = farthest;
    }
}
