// One blade as the grass dynamics reads and keeps it. Mirrors `GrassBlade`
// and `GrassState` in src/sim/grass.rs (std430: 144 and 32 bytes); a test
// compares the member offsets.
#ifndef MEADOW_GRASS_BLADE_GLSL
#define MEADOW_GRASS_BLADE_GLSL

// The motions, in the order of every per-motion vec4.
#define SWING  0
#define BEND_A 1   // bending of the rising edges (all edges of a non-drooping blade)
#define BEND_B 2   // bending of a drooping blade's falling edges
#define TWIST  3

struct GrassBlade {
    vec4 rest[4];    // xyz: rest control point P_i; w: per-blade random value
    vec4 width;      // xyz: rest E_w (unit, horizontal); w: half width (m)
    vec4 stiffness;  // k_i of edges 0, 1, 2 (root to tip); w: first edge of bending group B (3: none)
    vec4 drag;       // sigma S per motion
    vec4 inertia;    // I = m r^2 per motion
    vec4 damping;    // c per motion
};

struct GrassState {
    vec4 angle;      // theta per motion (rad)
    vec4 velocity;   // omega per motion (rad/s)
};

#endif
