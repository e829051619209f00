#version 450
#extension GL_GOOGLE_include_directive : require
// Depth pyramid, level 0, from a multisampled depth image
// (glsl/cull/pyramid_base.glsl).
#define PYRAMID_MULTISAMPLED

#include "pyramid_base.glsl"
