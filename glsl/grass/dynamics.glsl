// Grass dynamics (paper section 4; docs/method.md section 4): swinging, bending
// and twisting of one blade driven by the wind at its tip. The same model,
// function for function and in the same f32 arithmetic, as the CPU
// reference src/model/grass.rs, whose header gives the reading it takes.
#ifndef MEADOW_GRASS_DYNAMICS_GLSL
#define MEADOW_GRASS_DYNAMICS_GLSL

#include "grass_blade.glsl"

// MAX_ANGLE (the fold guard), MAX_WIND_SPEED (the runaway-field guard) and
// MIN_FLAT_TURN: src/interface/defs.rs (interface.glsl).
const vec3 UP = vec3(0.0, 1.0, 0.0);

// v rotated by `angle` about the unit `axis` (Rodrigues).
vec3 rotate_about(vec3 v, vec3 axis, float angle) {
    float s = sin(angle);
    float c = cos(angle);
    return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0 - c));
}

// The paper's ds: a unit direction, or zero when the motion is at rest.
vec3 direction_or_zero(vec3 v) {
    float l = length(v);
    return l > 1e-7 ? v / l : vec3(0.0);
}

vec3 normalize_or(vec3 v, vec3 fallback) {
    float l = length(v);
    return l > 1e-12 ? v / l : fallback;
}

vec3 rest_point(GrassBlade b, int i) {
    return i == 0 ? b.rest_root : i == 1 ? b.rest_1 : i == 2 ? b.rest_2 : b.rest_tip;
}

int split_edge(GrassBlade b) {
    return int(b.group_b_edge);
}

// x: the bending motion edge i belongs to; y: its group's local tip edge.
ivec2 bend_group(GrassBlade b, int i) {
    int split = split_edge(b);
    return i < split ? ivec2(BEND_A, split - 1) : ivec2(BEND_B, 2);
}

const float PI = 3.14159265358979;

// The turn about E_w that lays rest edge j flat toward the side theta bends
// to (`contact::flat_share`).
float flat_turn(GrassBlade b, int j, float theta) {
    vec3 along = cross(b.width_dir, UP);
    vec3 edge = rest_point(b, j + 1) - rest_point(b, j);
    float psi = atan(edge.y, dot(edge, along));
    return theta >= 0.0 ? psi : psi - PI;
}

// `contact::flat_share`: edge i's share in a fully pressed blade.
float flat_share(GrassBlade b, int i, float theta, float fallback) {
    float root = flat_turn(b, 0, theta);
    if (abs(root) < MIN_FLAT_TURN) {
        return fallback;
    }
    return flat_turn(b, i, theta) / root;
}

// `grass::bend_share`: edge i's share of its group's bending angle theta,
// eq. 12's k_tip / k_i moved toward the flat share as the blade is pressed.
float bend_share(GrassBlade b, int i, float theta, float pressed) {
    ivec2 group = bend_group(b, i);
    float share = b.stiffness[group.y] / b.stiffness[i];
    if (pressed == 0.0 || group.x != BEND_A) {
        return share;
    }
    return share + (flat_share(b, i, theta, share) - share) * pressed;
}

struct Pose {
    vec3 points[4];   // P0 (root) .. P3 (tip)
    vec3 e[3];        // E_e per edge
    vec3 w[3];        // E_w per edge: the rest E_w swung by the edge's share; bending turns about it
    vec3 n[3];        // E_n = E_w x E_e per edge
    vec3 w_local[3];  // the twisted E_w_local per edge
};

// The shape from the rest shape and the angles, root to tip: edge i bends
// about the rest E_w by its share of its group's angle and swings about the
// ground normal by its share of the swing angle (eq. 12 for both), and its
// width direction twists about the edge by its share of the twist.
// `pressed` (src/model/contact.rs) moves the rising edges' shares toward
// lying flat; 0 gives eq. 12's.
Pose blade_pose(GrassBlade b, vec4 angle, float pressed) {
    Pose p;
    vec3 w_rest = b.width_dir;
    vec3 k = b.stiffness;
    p.points[0] = rest_point(b, 0);
    for (int i = 0; i < 3; ++i) {
        ivec2 group = bend_group(b, i);
        float bend = bend_share(b, i, angle[group.x], pressed) * angle[group.x];
        float swing = k[2] / k[i] * angle[SWING];
        vec3 rest_edge = rest_point(b, i + 1) - rest_point(b, i);
        vec3 edge = rotate_about(rotate_about(rest_edge, w_rest, bend), UP, swing);
        p.points[i + 1] = p.points[i] + edge;
        p.e[i] = normalize_or(edge, UP);
        p.w[i] = rotate_about(w_rest, UP, swing);
    }
    for (int i = 0; i < 3; ++i) {
        p.n[i] = normalize_or(cross(p.w[i], p.e[i]), vec3(1.0, 0.0, 0.0));
        p.w_local[i] = rotate_about(p.w[i], p.e[i], k[2] / k[i] * angle[TWIST]);
    }
    return p;
}

vec3 flat_part(vec3 v) {
    return vec3(v.x, 0.0, v.z);
}

// Rest edge i on the ground plane, swung by its eq. 12 share of theta.
vec3 swung_flat_edge(GrassBlade b, int i, float theta) {
    vec3 rest_edge = rest_point(b, i + 1) - rest_point(b, i);
    return flat_part(rotate_about(rest_edge, UP, b.stiffness[2] / b.stiffness[i] * theta));
}

// The swing's lever (`swing_lever`): sum of s_i h_i(theta), by virtual work.
vec3 swing_lever(GrassBlade b, float theta) {
    vec3 lever = vec3(0.0);
    for (int i = 0; i < 3; ++i) {
        lever += swung_flat_edge(b, i, theta) * (b.stiffness[2] / b.stiffness[i]);
    }
    return lever;
}

// Swinging: the blade turns about the ground normal through its root, edge
// i by its eq. 12 share. W_S = S sigma (v . E_w) E_w (the tip edge's E_w),
// R_S = k_tip dtheta_s (G_static - G_cur) / |..|, both at the tip; lever
// `swing_lever`.
float swing_torque(GrassBlade b, Pose p, vec4 angle, vec3 wind, float give) {
    float theta = angle[SWING];
    vec3 g_static = vec3(0.0);
    vec3 g_cur = vec3(0.0);
    for (int i = 0; i < 3; ++i) {
        g_static += swung_flat_edge(b, i, 0.0);
        g_cur += swung_flat_edge(b, i, theta);
    }
    vec3 force = p.w[2] * (b.drag[SWING] * dot(wind, p.w[2]))
               + direction_or_zero(g_static - g_cur) * (b.stiffness[2] * abs(theta) * give);
    return dot(cross(swing_lever(b, theta), force), UP);
}

// Bending of one slope group: its local tip edge turns about E_w.
// W_B = S sigma (v . E_n) E_n, R_B = k dtheta_b (E_e_static - E_e_cur) / |..|
// with k the local tip edge's stiffness; lever: the local tip edge.
// E_e_static is the rest edge swung by its share of the swing, so that
// swinging never reads as bending.
float bend_torque(GrassBlade b, Pose p, int motion, vec4 angle, vec3 wind, float give) {
    int tip = motion == BEND_A ? split_edge(b) - 1 : 2;
    float theta = angle[motion];
    vec3 rest_edge = rest_point(b, tip + 1) - rest_point(b, tip);
    float swing = b.stiffness[2] / b.stiffness[tip] * angle[SWING];
    vec3 e_static = normalize_or(rotate_about(rest_edge, UP, swing), UP);
    vec3 n = p.n[tip];
    vec3 lever = p.points[tip + 1] - p.points[tip];
    vec3 force = n * (b.drag[motion] * dot(wind, n))
               + direction_or_zero(e_static - p.e[tip]) * (b.stiffness[tip] * abs(theta) * give);
    return dot(cross(lever, force), p.w[tip]);
}

// Twisting: the face turns about the tip edge E_e, on E_w_local only, with the
// untwisted E_w as its rest value, so bending never sees it.
// W_T = S sigma (v . E_n_local) E_n_local, E_n_local = E_w_local x E_e;
// R_T = k_tip dtheta_t (E_w - E_w_local) / |..|; lever: the half width along
// E_w_local, on the side the wind blows toward (side = +-1), which turns the
// face edge-on to the wind whichever way E_w points. The restoring force pulls
// that lever's end back toward its rest place, side * hw * E_w.
float twist_torque(GrassBlade b, Pose p, vec4 angle, vec3 wind) {
    float theta = angle[TWIST];
    vec3 e = p.e[2];
    vec3 w_local = p.w_local[2];
    vec3 n_local = normalize_or(cross(w_local, e), p.n[2]);
    float side = dot(wind, w_local) < 0.0 ? -1.0 : 1.0;
    vec3 force = n_local * (b.drag[TWIST] * dot(wind, n_local))
               + direction_or_zero(p.w[2] - w_local) * (side * b.stiffness[2] * abs(theta));
    return dot(cross(w_local * (side * b.half_width), force), e);
}

// lever x (W + R) along each motion's axis, plus the damping torque -c omega;
// the swing and bend restoring forces scaled by `give` (1 unless pressed).
vec4 torques(GrassBlade b, Pose p, GrassState s, vec3 wind, float give) {
    vec4 torque = vec4(swing_torque(b, p, s.angle, wind, give),
                       bend_torque(b, p, BEND_A, s.angle, wind, give),
                       0.0,
                       twist_torque(b, p, s.angle, wind));
    if (split_edge(b) < 3) {
        torque[BEND_B] = bend_torque(b, p, BEND_B, s.angle, wind, give);
    }
    return torque - b.damping * s.velocity;
}

// Non-finite wind counts as calm air; the speed is capped.
vec3 guard_wind(vec3 v) {
    if (any(isnan(v)) || any(isinf(v))) {
        return vec3(0.0);
    }
    float speed = length(v);
    return speed > MAX_WIND_SPEED ? v * (MAX_WIND_SPEED / speed) : v;
}

// The ground's upward unit normal at the root (`GrassBlade::ground_normal`:
// its x and z kept, its y positive).
vec3 ground_normal(GrassBlade b) {
    float x = b.ground_normal_x, z = b.ground_normal_z;
    return vec3(x, sqrt(max(1.0 - x * x - z * z, 0.0)), z);
}

// Whether a control point left the region over the ground at the root:
// n . (P - P0) >= c |P - P0|^2, c = `ground_curvature` (`Blade::ground_curvature`;
// the plane y = 0 on flat ground).
bool below_ground(GrassBlade b, Pose p) {
    vec3 root = b.rest_root;
    vec3 n = ground_normal(b);
    float c = b.ground_curvature;
    bool below = false;
    for (int i = 1; i < 4; i++) {
        vec3 d = p.points[i] - root;
        below = below || dot(d, n) < c * dot(d, d);
    }
    return below;
}

// Ground contact (ours): a substep that would bend the blade into the
// ground keeps its bending angles from before it and stops them.
void ground_contact(GrassBlade b, inout GrassState s, GrassState before) {
    if (ground_normal(b) != UP) {
        // On a slope swinging carries a bent blade over higher ground too.
        s.angle[SWING] = before.angle[SWING];
        s.velocity[SWING] = 0.0;
    }
    s.angle[BEND_A] = before.angle[BEND_A];
    s.velocity[BEND_A] = 0.0;
    s.angle[BEND_B] = before.angle[BEND_B];
    s.velocity[BEND_B] = 0.0;
}

// Defined in contact.glsl, which needs the pose above.
bool resolve_contacts(GrassBlade b, inout GrassState s, float pressed, inout Pose p, uvec4 near);
float press_give(float pressed);

// One simulation step in `substeps` symplectic Euler substeps of h:
// omega' = omega + (N / I) h, theta' = theta + omega' h, the damping in N
// taken at (omega + omega') / 2. A blade in the pressed state `pressed`, or
// colliders it can reach (the bits of `near`, in scene order), resolves its
// contacts after each substep (`grass::step_touching`); returns whether it
// touched one. Only step_touching.comp has the contact (step.glsl).
bool blade_step(GrassBlade b, inout GrassState s, vec3 wind, float h, uint substeps,
                float pressed, uvec4 near) {
    wind = guard_wind(wind);
    float give = press_give(pressed);
    bool touched = false;
    Pose p = blade_pose(b, s.angle, pressed);
    for (uint k = 0u; k < substeps; ++k) {
        vec4 torque = torques(b, p, s, wind, give);
        GrassState before = s;
        for (int m = 0; m < 4; ++m) {
            // Damping at the step's midpoint (`step` in src/model/grass.rs).
            float undamped = torque[m] + b.damping[m] * s.velocity[m];
            float a = 0.5 * h * b.damping[m] / b.inertia[m];
            float omega = (s.velocity[m] * (1.0 - a) + undamped / b.inertia[m] * h) / (1.0 + a);
            float theta = s.angle[m] + omega * h;
            if (abs(theta) > MAX_ANGLE) {
                s.angle[m] = theta < 0.0 ? -MAX_ANGLE : MAX_ANGLE;
                s.velocity[m] = 0.0;
            } else {
                s.angle[m] = theta;
                s.velocity[m] = omega;
            }
        }
        p = blade_pose(b, s.angle, pressed);
        if (below_ground(b, p)) {
            ground_contact(b, s, before);
            p = blade_pose(b, s.angle, pressed);
        }
#ifdef GRASS_TOUCHING
        if (any(notEqual(near, uvec4(0u))) || pressed != 0.0) {
            touched = resolve_contacts(b, s, pressed, p, near) || touched;
        }
#endif
    }
    return touched;
}

#endif
