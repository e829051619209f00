#version 450
#extension GL_GOOGLE_include_directive : require
// The grass step for the blades near a collider or pressed, which
// step.comp listed (glsl/grass/step.glsl).
#define GRASS_TOUCHING

#include "step.glsl"
