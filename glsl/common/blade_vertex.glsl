// One control point of a blade as the render pipeline reads it: the buffer the
// grass dynamics writes and the vertex stage draws, four `BladeVertex` per
// blade (src/interface/defs.rs, 32 bytes each).
//   position.xyz: control point P_i in world space
//   position.w:   per-blade random value in [0, 1) (colour variation)
//   width.xyz:    half-width vector of the blade at P_i (E_w times half width)
//   width.w:      angular displacement from rest in radians (motion view)
#ifndef MEADOW_BLADE_VERTEX_GLSL
#define MEADOW_BLADE_VERTEX_GLSL
#include "interface.glsl"
#define BLADE_CONTROL_POINTS 4
#endif
