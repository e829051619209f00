#version 450
#extension GL_GOOGLE_include_directive : require
// Depth pyramid, level 0, from a single-sample depth image
// (glsl/cull/pyramid_base.glsl).

#include "pyramid_base.glsl"
