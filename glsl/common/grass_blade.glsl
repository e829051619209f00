// One blade as the grass dynamics reads and keeps it: `GrassBlade` and
// `GrassState`, written once in src/interface/defs.rs (std430: 144 and 32
// bytes).
#ifndef MEADOW_GRASS_BLADE_GLSL
#define MEADOW_GRASS_BLADE_GLSL

// The motions, in the order of every per-motion vec4.
#define SWING  0
#define BEND_A 1   // bending of the rising edges (all edges of a non-drooping blade)
#define BEND_B 2   // bending of a drooping blade's falling edges
#define TWIST  3

// GrassBlade and GrassState: src/interface/defs.rs.
#include "interface.glsl"

#endif
