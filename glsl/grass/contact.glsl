// Touch (ours; docs/physics.md, "Colliders"): spheres and upright capsules
// press the grass. The same model, function for function and in the same f32
// arithmetic, as the CPU reference src/model/contact.rs, whose header gives it.
// Compute only: the including kernel declares the colliders at the step's
// end and defines COLLIDER_STATE(c), collider c of them.
#ifndef MEADOW_GRASS_CONTACT_GLSL
#define MEADOW_GRASS_CONTACT_GLSL

#include "collider.glsl"

// CONTACT_ITERATIONS, CONTACT_SLOP, MAX_CORRECTION, PRESS_SOFTENING and
// PRESS_RISE_TIME: src/interface/defs.rs (interface.glsl).
#define CONTACT_SAMPLES 10

// `Press` (src/interface/defs.rs) holds the pressed state the last step
// used, and 1 if it touched a collider.

// The points tested against colliders, as weights of P0..P3 (`SAMPLES`):
// P1, P2, P3 and the drawn curve at u = 1/8 .. 7/8 (Bernstein weights).
const vec4 CONTACT_SAMPLE_WEIGHTS[CONTACT_SAMPLES] = vec4[](
    vec4(0.0, 1.0, 0.0, 0.0),
    vec4(0.0, 0.0, 1.0, 0.0),
    vec4(0.0, 0.0, 0.0, 1.0),
    vec4(0.669921875, 0.287109375, 0.041015625, 0.001953125),
    vec4(0.421875, 0.421875, 0.140625, 0.015625),
    vec4(0.244140625, 0.439453125, 0.263671875, 0.052734375),
    vec4(0.125, 0.375, 0.375, 0.125),
    vec4(0.052734375, 0.263671875, 0.439453125, 0.244140625),
    vec4(0.015625, 0.140625, 0.421875, 0.421875),
    vec4(0.001953125, 0.041015625, 0.287109375, 0.669921875));

vec3 contact_sample(Pose p, vec4 w) {
    return p.points[0] * w.x + p.points[1] * w.y + p.points[2] * w.z + p.points[3] * w.w;
}

// `contact::reach`: the sum of the rest edge lengths.
float blade_reach(GrassBlade b) {
    float r = 0.0;
    for (int i = 0; i < 3; ++i) {
        r += length(rest_point(b, i + 1) - rest_point(b, i));
    }
    return r;
}

// `contact::give`: the factor on the swing and bend restoring forces.
float press_give(float pressed) {
    return 1.0 - PRESS_SOFTENING * pressed;
}

// `Press::next`: the pressed state of the next step of dt.
float press_next(Press press, float dt, float decay) {
    return press.touched != 0.0 ? min(press.pressed + dt / PRESS_RISE_TIME, 1.0)
                                : press.pressed * decay;
}

// `point_rates`: dP_j / dtheta_m, j = 1..3 (first index j - 1), m = swing,
// bend A, bend B.
void point_rates(GrassBlade b, vec4 angle, float pressed, Pose p, out vec3 rates[3][3]) {
    vec3 k = b.stiffness;
    vec3 below[3] = vec3[](vec3(0.0), vec3(0.0), vec3(0.0));
    for (int i = 0; i < 3; ++i) {
        vec3 edge = p.points[i + 1] - p.points[i];
        ivec2 group = bend_group(b, i);
        vec3 swing = cross(UP, edge) * (k[2] / k[i]);
        vec3 bend = cross(p.w[i], edge) * bend_share(b, i, angle[group.x], pressed);
        below[0] += swing;
        if (group.x == BEND_A) {
            below[1] += bend;
        } else {
            below[2] += bend;
        }
        rates[i] = below;
    }
}

// `contact::resolve`: up to CONTACT_ITERATIONS projections of the deepest
// point (the ground first), each with its velocity impulse. Returns whether
// a collider was touched; p is left the pose of the state. `near`: the
// colliders this blade can reach, one bit each in scene order, its own
// list (`contact::near_blade`).
bool resolve_contacts(GrassBlade b, inout GrassState s, float pressed, inout Pose p, uvec4 near) {
    bool touched = false;
    int moved = split_edge(b) < 3 ? 3 : 2;
    for (int it = 0; it < CONTACT_ITERATIONS; ++it) {
        int sample_index = -1;
        float depth = 0.0;
        vec3 normal = UP;
        vec3 surface_velocity = vec3(0.0);
        bool ground = false;
        for (int k = 0; k < CONTACT_SAMPLES; ++k) {
            float y = contact_sample(p, CONTACT_SAMPLE_WEIGHTS[k]).y;
            if (y < 0.0 && (sample_index < 0 || -y > depth)) {
                sample_index = k;
                depth = -y;
                normal = UP;
                surface_velocity = vec3(0.0);
                ground = true;
            }
        }
        if (sample_index < 0) {
            for (uint word = 0u; word < 4u; ++word) {
              for (uint bits = near[word]; bits != 0u; bits &= bits - 1u) {
                uint c = word * 32u + uint(findLSB(bits));
                for (int k = 0; k < CONTACT_SAMPLES; ++k) {
                    vec4 d = collider_distance(COLLIDER_STATE(c), contact_sample(p, CONTACT_SAMPLE_WEIGHTS[k]));
                    if (d.x < 0.0 && (sample_index < 0 || -d.x > depth)) {
                        sample_index = k;
                        depth = -d.x;
                        normal = d.yzw;
                        surface_velocity = COLLIDER_STATE(c).velocity.xyz;
                    }
                }
              }
            }
        }
        if (sample_index < 0) {
            break;
        }
        touched = touched || !ground;
        vec3 rates[3][3];
        point_rates(b, s.angle, pressed, p, rates);
        vec4 w = CONTACT_SAMPLE_WEIGHTS[sample_index];
        float g[3] = float[](0.0, 0.0, 0.0);
        float denominator = 0.0;
        for (int j = 0; j < moved; ++j) {
            vec3 rate = rates[0][j] * w.y + rates[1][j] * w.z + rates[2][j] * w.w;
            g[j] = dot(normal, rate);
            denominator += g[j] * g[j] / b.inertia[j];
        }
        if (denominator <= 1e-12) {
            break;
        }
        float lambda = (depth + CONTACT_SLOP) / denominator;
        for (int j = 0; j < moved; ++j) {
            float change = clamp(g[j] / b.inertia[j] * lambda, -MAX_CORRECTION, MAX_CORRECTION);
            s.angle[j] = clamp(s.angle[j] + change, -MAX_ANGLE, MAX_ANGLE);
        }
        float normal_speed = 0.0;
        for (int j = 0; j < moved; ++j) {
            normal_speed += g[j] * s.velocity[j];
        }
        float surface_speed = dot(normal, surface_velocity);
        if (normal_speed < surface_speed) {
            float impulse = (surface_speed - normal_speed) / denominator;
            for (int j = 0; j < moved; ++j) {
                s.velocity[j] += g[j] / b.inertia[j] * impulse;
            }
        }
        p = blade_pose(b, s.angle, pressed);
    }
    return touched;
}

#endif
