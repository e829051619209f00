// One control point of a blade as the render pipeline reads it: the buffer the
// grass dynamics writes and the vertex stage draws, four `BladeVertex` per
// blade (src/interface/defs.rs, 32 bytes each: position, blade_rand,
// half_width, displacement).
#ifndef MEADOW_BLADE_VERTEX_GLSL
#define MEADOW_BLADE_VERTEX_GLSL
#include "interface.glsl"
#define BLADE_CONTROL_POINTS 4
#endif
