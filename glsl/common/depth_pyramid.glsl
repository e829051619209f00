// The depth pyramid (src/render/depth_pyramid.rs): the colour pass's depth
// of one frame, each texel the farthest depth of what it covers, level 0
// one texel per pixel (the farthest of its samples), each level above half
// the one below (rounded up), all levels one after another in one buffer.
// The cull pass of the next frame tests blades against it.
#ifndef MEADOW_DEPTH_PYRAMID_GLSL
#define MEADOW_DEPTH_PYRAMID_GLSL

// Where level `level` of the pyramid over `base` (level 0's size) starts
// in the buffer, and its size.
uvec3 pyramid_level(uvec2 base, uint level) {
    uint offset = 0u;
    uvec2 size = base;
    for (uint k = 0u; k < level; ++k) {
        offset += size.x * size.y;
        size = (size + 1u) / 2u;
    }
    return uvec3(offset, size);
}

#endif
