#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, the V-cycle's coarse levels in one workgroup
// (mg_tail.glsl), in 48 KiB of shared memory, for devices that offer it.
#define TAIL_CAPACITY MG_TAIL_FLOATS_LARGE
#include "mg_tail.glsl"
