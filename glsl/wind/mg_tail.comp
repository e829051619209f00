#version 450
#extension GL_GOOGLE_include_directive : require
// Multigrid, the V-cycle's coarse levels in one workgroup
// (mg_tail.glsl), in the 16 KiB of shared memory every device offers.
#define TAIL_CAPACITY MG_TAIL_FLOATS
#include "mg_tail.glsl"
