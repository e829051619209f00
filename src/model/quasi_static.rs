//! The quasi-static pose (ours; issue 40's far field): the angles at which
//! a blade's torques balance in a steady wind, the state the paper's
//! dynamics (src/model/grass.rs) settle into when the wind holds still,
//! found without stepping them and without keeping any state. Beyond the
//! radius where blades are simulated, a blade shows this pose for the wind
//! sampled there.
//!
//! The balance is `grass::torques` = 0 at zero angular velocity: four
//! equations in the four angles (three on a blade with one bending group,
//! whose second bending angle stays 0). A strong wind has more than one
//! balance (a blade swung to either side; the unstable one between), so
//! plain Newton from rest can land on the wrong one. Pseudo-transient
//! continuation follows the way the blade gives instead: each step solves
//! (c K - J) d = T, J the Jacobian of the torques by central differences,
//! K the diagonal of -J at rest in still air (each motion's restoring
//! stiffness), and c, large
//! at first (a small, overdamped step down the torque), shrinks as the
//! torque does (switched evolution relaxation), and by at least
//! `RELAXATION_SHRINK` an iteration, until the step is Newton's.
//! Each step turns an angle by at most `MAX_TURN`.

use glam::Vec3;

use crate::model::grass::{self, GrassBlade, GrassState, BEND_B, MAX_ANGLE};

/// Iterations at most (table1's blades in 1-6 m/s balance in at most 16).
pub const MAX_ITERATIONS: usize = 100;
/// Iterations the far field's pose takes at most (the cover's, on the GPU
/// and in its CPU reference): table1's blades in 1-6 m/s are within 3.2e-5
/// of the settled angles after 12, within 9% after 10.
pub use crate::interface::QUASI_STATIC_ITERATIONS as FAR_ITERATIONS;
// The solve's constants are the GPU's (src/interface), in f64 here where
// the reference computes in f64.
/// The pseudo-time term's first (and largest) weight, in units of the
/// still-air stiffness.
const START_RELAXATION: f64 = crate::interface::QS_START_RELAXATION as f64;
/// The weight falls at least this much each iteration, and more as the
/// torque does: from 10 it reaches Newton's step in a dozen iterations,
/// where following the torque alone took up to 56. Faster (0.5) lands
/// one of 732 blade-winds at 6 m/s on the other side's balance.
const RELAXATION_SHRINK: f64 = crate::interface::QS_RELAXATION_SHRINK as f64;
/// The largest change of an angle in one iteration (rad).
const MAX_TURN: f64 = crate::interface::QS_MAX_TURN as f64;
/// Central-difference step of the Jacobian (rad).
const DIFFERENCE: f32 = crate::interface::QS_DIFFERENCE;
/// Done when no angle changes by more than this (rad).
const TOLERANCE: f64 = crate::interface::QS_TOLERANCE as f64;

/// The angles (swing, bend A, bend B, twist) at which `blade`'s torques
/// balance in the steady `wind` (m/s, at its tip), and the iterations
/// taken. Angles stay within `MAX_ANGLE`, as the dynamics' guard keeps them.
pub fn quasi_static_angles(blade: &GrassBlade, wind: Vec3) -> ([f32; 4], usize) {
    quasi_static_angles_within(blade, wind, MAX_ITERATIONS)
}

/// `quasi_static_angles` stopped after at most `iterations`: where the
/// continuation has got to by then.
pub fn quasi_static_angles_within(
    blade: &GrassBlade,
    wind: Vec3,
    iterations: usize,
) -> ([f32; 4], usize) {
    quasi_static_angles_from(blade, wind, [0.0; 4], iterations)
}

/// `quasi_static_angles_within` continued from `start` rather than from
/// rest: the balance the blade gives into from there, on the side it
/// stands (a far blade from last frame's pose: in a strong wind the side
/// it was on, not the other side's).
pub fn quasi_static_angles_from(
    blade: &GrassBlade,
    wind: Vec3,
    start: [f32; 4],
    iterations: usize,
) -> ([f32; 4], usize) {
    let wind = grass::guard_wind(wind);
    let motions: Vec<usize> = (0..4)
        .filter(|&m| m != BEND_B || blade.split() < 3)
        .collect();
    let torque = |angle: [f32; 4]| torque_at(blade, angle, wind);
    let n = motions.len();
    let jacobian_in = |angle: [f32; 4], wind: Vec3| torque_jacobian(blade, &motions, angle, wind);
    let norm = |t: [f32; 4]| {
        motions
            .iter()
            .map(|&m| (t[m] as f64).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    // Each motion's restoring stiffness at rest in still air (-J's
    // diagonal there), the scale of the pseudo-time term. The wind can
    // make a motion unstable at rest (its torque growing with the angle),
    // so the term starts well above what the wind adds.
    let still = jacobian_in([0.0; 4], Vec3::ZERO);
    let mut angle = start;
    if blade.split() >= 3 {
        angle[BEND_B] = 0.0;
    }
    let stiffness: Vec<f64> = (0..n).map(|i| (-still[i][i]).max(1e-12)).collect();
    let mut relax = START_RELAXATION;
    let mut last_norm = norm(torque(angle));
    for iteration in 1..=iterations {
        let t = torque(angle);
        let now = norm(t);
        let fall = (now / last_norm.max(f64::MIN_POSITIVE)).min(RELAXATION_SHRINK);
        relax = (relax * fall).min(START_RELAXATION);
        last_norm = now;
        let mut system = jacobian_in(angle, wind);
        for (i, row) in system.iter_mut().enumerate() {
            for value in row.iter_mut() {
                *value = -*value;
            }
            row[i] += relax * stiffness[i];
        }
        let rhs: Vec<f64> = motions.iter().map(|&i| t[i] as f64).collect();
        let Some(delta) = solve(system, rhs) else {
            return (angle, iteration);
        };
        let largest = delta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let scale = if largest > MAX_TURN {
            MAX_TURN / largest
        } else {
            1.0
        };
        for (&m, d) in motions.iter().zip(&delta) {
            angle[m] = (angle[m] + (d * scale) as f32).clamp(-MAX_ANGLE, MAX_ANGLE);
        }
        if largest < TOLERANCE && relax < 1e-3 {
            return (angle, iteration);
        }
    }
    (angle, iterations)
}

/// The torques on `blade` held still at `angle` in `wind`.
fn torque_at(blade: &GrassBlade, angle: [f32; 4], wind: Vec3) -> [f32; 4] {
    let state = GrassState {
        angle,
        velocity: [0.0; 4],
    };
    grass::torques(blade, &grass::pose(blade, angle), &state, wind)
}

/// The Jacobian d torque_i / d angle_j over `motions` at `angle` in
/// `wind`, by central differences.
fn torque_jacobian(
    blade: &GrassBlade,
    motions: &[usize],
    angle: [f32; 4],
    wind: Vec3,
) -> Vec<Vec<f64>> {
    let n = motions.len();
    let mut j = vec![vec![0.0f64; n]; n];
    for (col, &m) in motions.iter().enumerate() {
        let (mut plus, mut minus) = (angle, angle);
        plus[m] += DIFFERENCE;
        minus[m] -= DIFFERENCE;
        let (tp, tm) = (torque_at(blade, plus, wind), torque_at(blade, minus, wind));
        for (row, &i) in motions.iter().enumerate() {
            j[row][col] = (tp[i] - tm[i]) as f64 / (2.0 * DIFFERENCE as f64);
        }
    }
    j
}

/// The natural frequency (rad/s) a far blade goes towards its balance at
/// (`far_tracked`): the slowest of its motions' sqrt(k_eff / I) in still
/// air (`GrassBlade::k_eff`, `inertia`), as a flip to the other side
/// moves them all together and takes as long as the slowest.
pub fn far_frequency(blade: &GrassBlade) -> f32 {
    let k = blade.k_eff();
    (0..4)
        .filter(|&m| m != BEND_B || blade.split() < 3)
        .map(|m| (k[m] / blade.inertia[m]).max(0.0).sqrt())
        .fold(f32::INFINITY, f32::min)
}

/// A far blade's angles and rates `elapsed` seconds on (issue 65, item 7:
/// no popping). A stateless balance jumps where a strong wind's two
/// balances trade places (the continuation lands on the other side's), so
/// each frame the far blade goes from last frame's pose towards this
/// frame's balance `target` as a critically damped blade of natural
/// frequency `omega` would (`far_frequency`), the balance held over the
/// frame: theta'' =
/// omega^2 (target - theta) - 2 omega theta', solved exactly (e = theta -
/// target: e(t) = (e0 + (v0 + omega e0) t) e^(-omega t)), so any frame
/// time is stable and the same time in more frames ends nearly where it
/// does in fewer. Critically damped: it adds no sway of its own (the far
/// field keeps showing the wind), and a flip of D takes about 2 / omega
/// seconds, its tip moving at most omega D / e.
pub fn far_tracked(
    from: ([f32; 4], [f32; 4]),
    target: [f32; 4],
    omega: f32,
    elapsed: f32,
) -> ([f32; 4], [f32; 4]) {
    let (angle, velocity) = from;
    let fade = (-omega * elapsed).exp();
    let mut out = ([0.0f32; 4], [0.0f32; 4]);
    for m in 0..4 {
        let e0 = angle[m] - target[m];
        let c = velocity[m] + omega * e0;
        let e = (e0 + c * elapsed) * fade;
        out.0[m] = (target[m] + e).clamp(-MAX_ANGLE, MAX_ANGLE);
        out.1[m] = (velocity[m] - omega * c * elapsed) * fade;
    }
    out
}

/// `a x = b` by Gaussian elimination with partial pivoting; None when `a`
/// is singular (a blade the wind cannot move in some motion).
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))?;
        if a[pivot][col].abs() < 1e-18 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for (offset, row) in lower.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            for (value, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *value -= f * p;
            }
            b[col + 1 + offset] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let sum: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - sum) / a[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::{far_tracked, solve};

    /// `far_tracked` solves theta'' = omega^2 (target - theta) - 2 omega
    /// theta' (its second difference against the right side), steps of any
    /// length compose (one frame of 2 dt is two of dt), and a flip of D
    /// goes over without overshooting, its rate at most omega D / e.
    #[test]
    fn a_far_blade_goes_to_its_balance_as_a_critically_damped_blade() {
        let (omega, target) = (6.0f32, [0.4f32, -1.2, 0.0, 0.3]);
        let start = ([-0.6f32, 0.9, 0.0, 0.0], [0.0f32; 4]);
        let at = |t: f32| far_tracked(start, target, omega, t);
        let h = 1e-2f32;
        for t in [0.05f32, 0.2, 0.5] {
            let (before, now, after) = (at(t - h).0, at(t), at(t + h).0);
            for m in 0..4 {
                let second = (after[m] - 2.0 * now.0[m] + before[m]) / (h * h);
                let wanted = omega * omega * (target[m] - now.0[m]) - 2.0 * omega * now.1[m];
                let rate = (after[m] - before[m]) / (2.0 * h);
                assert!(
                    (second - wanted).abs() < 2e-2 * (1.0 + wanted.abs()),
                    "t {t} motion {m}: theta'' {second}, the equation {wanted}"
                );
                assert!(
                    (rate - now.1[m]).abs() < 1e-2 * (1.0 + now.1[m].abs()),
                    "t {t}: rate {rate} against {}",
                    now.1[m]
                );
            }
        }
        let (dt, mut twice) = (1.0 / 30.0, start);
        for _ in 0..2 {
            twice = far_tracked(twice, target, omega, dt);
        }
        let once = at(2.0 * dt);
        for m in 0..4 {
            assert!(
                (twice.0[m] - once.0[m]).abs() < 1e-6,
                "{twice:?} against {once:?}"
            );
        }
        // The flip of bend A, 2.1 rad: no overshoot, its rate at most
        // omega D / e, and settled within 1e-4 rad after 3 s.
        let d = target[1] - start.0[1];
        let mut fastest = 0.0f32;
        let mut state = start;
        for _ in 0..90 {
            state = far_tracked(state, target, omega, 1.0 / 30.0);
            assert!(state.0[1] >= target[1] - 1e-6, "overshot: {}", state.0[1]);
            fastest = fastest.max(state.1[1].abs());
        }
        let bound = omega * d.abs() / std::f32::consts::E;
        assert!(fastest <= bound * 1.0001, "{fastest} rad/s against {bound}");
        assert!(fastest > 0.9 * bound, "{fastest} rad/s against {bound}");
        assert!((state.0[1] - target[1]).abs() < 1e-4, "{}", state.0[1]);
        // No time, no move (to the sum's rounding).
        let still = far_tracked(start, target, omega, 0.0);
        for m in 0..4 {
            assert!((still.0[m] - start.0[m]).abs() < 1e-6, "{still:?}");
            assert_eq!(still.1[m], start.1[m]);
        }
    }

    #[test]
    fn solves_a_small_system_and_refuses_a_singular_one() {
        let x = solve(
            vec![
                vec![0.0, 2.0, 1.0],
                vec![1.0, 1.0, 0.0],
                vec![3.0, 0.0, 1.0],
            ],
            vec![5.0, 3.0, 6.0],
        )
        .unwrap();
        for (got, want) in x.iter().zip([1.4, 1.6, 1.8]) {
            assert!((got - want).abs() < 1e-12, "{x:?}");
        }
        assert!(solve(vec![vec![1.0, 2.0], vec![2.0, 4.0]], vec![1.0, 2.0]).is_none());
    }
}
