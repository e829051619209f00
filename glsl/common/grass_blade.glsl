// One blade as the grass dynamics reads and keeps it: `GrassBlade` and
// `GrassState`, written once in src/interface/defs.rs (std430: 144 and 32
// bytes).
#ifndef MEADOW_GRASS_BLADE_GLSL
#define MEADOW_GRASS_BLADE_GLSL

// The motions, in the order of every per-motion vec4 (SWING, BEND_A,
// BEND_B, TWIST): src/interface/defs.rs (interface.glsl).

// GrassBlade and GrassState: src/interface/defs.rs.
#include "interface.glsl"

#endif
