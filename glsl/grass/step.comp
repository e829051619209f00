#version 450
#extension GL_GOOGLE_include_directive : require
// The grass step for every blade but those near a collider or pressed
// (glsl/grass/step.glsl).

#include "step.glsl"
