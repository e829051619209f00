// The quasi-static pose (ours; `quasi_static_angles` in
// src/model/quasi_static.rs, whose header gives the method): the angles at
// which a blade's torques balance at rest in a steady wind, found by
// pseudo-transient continuation, (c K - J) d = T, J by central differences,
// K the still-air stiffness at rest, c from 10 down as the torque falls,
// by at least 0.6 an iteration; at most QUASI_STATIC_ITERATIONS of them
// (`quasi_static_angles_within(.., FAR_ITERATIONS)`).
// The same steps in f32 (the CPU solves its small system in f64), so the
// two agree to the solve's tolerance, not bit for bit.
#ifndef MEADOW_QUASI_STATIC_GLSL
#define MEADOW_QUASI_STATIC_GLSL

#include "dynamics.glsl"

// QS_START_RELAXATION, QS_RELAXATION_SHRINK, QS_MAX_TURN, QS_DIFFERENCE
// and QS_TOLERANCE come from interface.glsl (src/interface/defs.rs).

vec4 qs_torque(GrassBlade b, vec4 angle, vec3 wind) {
    GrassState s = GrassState(angle, vec4(0.0));
    return torques(b, blade_pose(b, angle, 0.0), s, wind, 1.0);
}

// 1 for each motion the blade has (the second bending group's only with
// two groups).
vec4 qs_motions(GrassBlade b) {
    return vec4(1.0, 1.0, split_edge(b) < 3 ? 1.0 : 0.0, 1.0);
}

// d torque / d angle, column m the motion m varied (a motion the blade
// does not have: a zero column).
mat4 qs_jacobian(GrassBlade b, vec4 angle, vec3 wind, vec4 used) {
    mat4 j = mat4(0.0);
    for (int m = 0; m < 4; ++m) {
        if (used[m] != 0.0) {
            vec4 plus = angle;
            vec4 minus = angle;
            plus[m] += QS_DIFFERENCE;
            minus[m] -= QS_DIFFERENCE;
            j[m] = (qs_torque(b, plus, wind) - qs_torque(b, minus, wind)) / (2.0 * QS_DIFFERENCE);
        }
    }
    return j;
}

// a x = r (a column-major) by Gaussian elimination with partial pivoting;
// false when a is singular.
bool qs_solve(mat4 a, vec4 r, out vec4 x) {
    float m[4][5];
    for (int row = 0; row < 4; ++row) {
        for (int col = 0; col < 4; ++col) {
            m[row][col] = a[col][row];
        }
        m[row][4] = r[row];
    }
    for (int col = 0; col < 4; ++col) {
        int pivot = col;
        for (int row = col + 1; row < 4; ++row) {
            if (abs(m[row][col]) > abs(m[pivot][col])) {
                pivot = row;
            }
        }
        if (abs(m[pivot][col]) < 1e-30) {
            x = vec4(0.0);
            return false;
        }
        for (int k = 0; k < 5; ++k) {
            float t = m[col][k];
            m[col][k] = m[pivot][k];
            m[pivot][k] = t;
        }
        for (int row = col + 1; row < 4; ++row) {
            float f = m[row][col] / m[col][col];
            for (int k = col; k < 5; ++k) {
                m[row][k] -= f * m[col][k];
            }
        }
    }
    for (int row = 3; row >= 0; --row) {
        float sum = m[row][4];
        for (int k = row + 1; k < 4; ++k) {
            sum -= m[row][k] * x[k];
        }
        x[row] = sum / m[row][row];
    }
    return true;
}

float qs_norm(vec4 t, vec4 used) {
    return length(t * used);
}

// The balance's angles (swing, bend A, bend B, twist) for `wind` at the
// tip, continued from `start` (`quasi_static_angles_from`; from rest:
// `quasi_static_angles_within`).
vec4 quasi_static_angles_from(GrassBlade b, vec3 wind, vec4 start) {
    wind = guard_wind(wind);
    vec4 used = qs_motions(b);
    mat4 still = qs_jacobian(b, vec4(0.0), vec3(0.0), used);
    vec4 angle = start * used;
    vec4 stiffness = vec4(1.0);
    for (int m = 0; m < 4; ++m) {
        stiffness[m] = max(-still[m][m], 1e-12);
    }
    float relax = QS_START_RELAXATION;
    float last_norm = qs_norm(qs_torque(b, angle, wind), used);
    for (int iteration = 0; iteration < int(QUASI_STATIC_ITERATIONS); ++iteration) {
        vec4 t = qs_torque(b, angle, wind) * used;
        float now = qs_norm(t, used);
        relax = min(relax * min(now / max(last_norm, 1e-37), QS_RELAXATION_SHRINK), QS_START_RELAXATION);
        last_norm = now;
        mat4 system = -qs_jacobian(b, angle, wind, used);
        for (int m = 0; m < 4; ++m) {
            // A motion the blade lacks: d = 0.
            system[m][m] = used[m] != 0.0 ? system[m][m] + relax * stiffness[m] : 1.0;
        }
        vec4 delta;
        if (!qs_solve(system, t, delta)) {
            break;
        }
        delta *= used;
        float largest = max(max(abs(delta.x), abs(delta.y)), max(abs(delta.z), abs(delta.w)));
        float scale = largest > QS_MAX_TURN ? QS_MAX_TURN / largest : 1.0;
        angle = clamp(angle + delta * scale, vec4(-MAX_ANGLE), vec4(MAX_ANGLE));
        if (largest < QS_TOLERANCE && relax < 1e-3) {
            break;
        }
    }
    return angle;
}

vec4 quasi_static_angles(GrassBlade b, vec3 wind) {
    return quasi_static_angles_from(b, wind, vec4(0.0));
}

// `quasi_static::far_frequency`: the slowest of the blade's motions'
// sqrt(k_eff / I) (`GrassBlade::k_eff`; its inertia as `GrassBlade::new`
// makes it).
float far_frequency(GrassBlade b) {
    int split = split_edge(b);
    int tip_a = split - 1;
    vec4 k_eff = vec4(
        length(swing_lever(b, 0.0)) * b.stiffness[2],
        distance(rest_point(b, tip_a + 1), rest_point(b, tip_a)) * b.stiffness[tip_a],
        split < 3 ? distance(rest_point(b, 3), rest_point(b, 2)) * b.stiffness[2] : 0.0,
        b.half_width * b.stiffness[2]);
    vec4 w = sqrt(max(k_eff / b.inertia, vec4(0.0)));
    return min(min(w.x, w.y), min(split < 3 ? w.z : w.x, w.w));
}

// `quasi_static::far_tracked`: angles and rates `elapsed` seconds on, from
// `angle`, `velocity` towards the balance `target` as a critically damped
// blade of natural frequency `omega` (rad/s) goes, solved exactly.
void far_tracked(inout vec4 angle, inout vec4 velocity, vec4 target, float omega, float elapsed) {
    float fade = exp(-omega * elapsed);
    vec4 e0 = angle - target;
    vec4 c = velocity + omega * e0;
    angle = clamp(target + (e0 + c * elapsed) * fade, vec4(-MAX_ANGLE), vec4(MAX_ANGLE));
    velocity = (velocity - omega * c * elapsed) * fade;
}

#endif
