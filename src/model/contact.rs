//! Touch (ours; the paper leaves collisions as future work; docs/physics.md,
//! "Colliders"): spheres and upright capsules moving through the meadow
//! press the grass, and it recovers. The CPU reference; glsl/grass/contact.glsl
//! is the same arithmetic in f32, and tests/grass_gpu.rs compares the two.
//!
//! The contact model, within the paper's motions:
//! - a blade touches a collider when a point of its drawn curve lies inside
//!   it: the control points P1..P3 and the Bezier curve at u = 1/8, 2/8,
//!   .., 7/8 (`SAMPLES`); the root is fixed;
//! - each substep, after the paper's update, the deepest such point is
//!   pushed out along the collider's normal by changing the swing and
//!   bending angles (the only motions that move points) by the smallest
//!   inertia-weighted change that does it (`CONTACT_ITERATIONS` times):
//!   the position half of an inelastic contact, like the ground contact;
//! - the velocity half is the contact torque: an impulse in the swing and
//!   bending torques that leaves the touching point moving away from the
//!   collider no slower than the collider's own surface moves (a ball
//!   rolling over a blade drags it along);
//! - a blade that touches a collider is pressed: its `pressed` state rises
//!   to 1 over PRESS_RISE_TIME and decays by exp(-dt / PRESS_DECAY_TIME)
//!   each untouched step. Pressed, a blade is a crushed stem: its swing
//!   and bend restoring forces weaken by 1 - PRESS_SOFTENING * pressed,
//!   and its edges share the bending angle more evenly (`bend_share`: the
//!   root gives way, so it can lie down under a ball). It rises again
//!   slowly as the state decays, so a rolling ball leaves a trail.
//!
//! Roots stay put and edge lengths stay exact because the contact, like
//! everything else, acts only on the angles of `grass::pose`.

use glam::Vec3;

/// The band (m) inside a cover's `simulate_radius` over which a kept
/// blade's pressing fades out (`scene::cover::pressed_fade`;
/// glsl/cover/tiles.comp reads the same).
pub use crate::interface::COVER_PRESS_FADE_M as PRESS_FADE_M;

use crate::model::grass::{
    bend_share, pressed_pose, step_with, GrassBlade, GrassState, Pose, BEND_A, BEND_B, MAX_ANGLE,
    SWING,
};

/// The most colliders a scene may have (src/interface/defs.rs: the
/// collider bins hold a bit for each).
pub use crate::interface::MAX_COLLIDERS;
/// What presses the grass: src/model/collider.rs.
pub use crate::model::collider::{Collider, ColliderKind, ColliderState, GpuCollider};

/// Projections per substep, their slop and largest correction, and the
/// pressed state's rise: written once for both sides (src/interface).
pub use crate::interface::{CONTACT_ITERATIONS, CONTACT_SLOP, MAX_CORRECTION, PRESS_RISE_TIME};

/// The time constant of the pressed state's decay (s).
pub const PRESS_DECAY_TIME: f32 = 1.0;

/// The points of a blade tested against colliders, as weights of
/// P0..P3: the control points P1, P2, P3 and the drawn curve at u = 1/8,
/// 2/8, .., 7/8 (Bernstein weights).
pub const SAMPLES: [[f32; 4]; 10] = [
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
    bernstein(0.125),
    bernstein(0.25),
    bernstein(0.375),
    bernstein(0.5),
    bernstein(0.625),
    bernstein(0.75),
    bernstein(0.875),
];

const fn bernstein(u: f32) -> [f32; 4] {
    let v = 1.0 - u;
    [v * v * v, 3.0 * v * v * u, 3.0 * v * u * u, u * u * u]
}

/// The longest distance any point of the blade can be from its root: the
/// sum of its edge lengths.
pub fn reach(blade: &GrassBlade) -> f32 {
    let mut r = 0.0f32;
    for i in 0..3 {
        r += (blade.rest_point(i + 1) - blade.rest_point(i)).length();
    }
    r
}

/// dP_j / dtheta_m for j = 1..3 and m = swing, bend A, bend B: edge i
/// turns about UP by its swing share and about its swung E_w by its bend
/// share (`grass::pose`), so d edge_i = share * (axis x edge_i), summed
/// root to tip.
fn point_rates(blade: &GrassBlade, angle: [f32; 4], pressed: f32, p: &Pose) -> [[Vec3; 3]; 3] {
    let k = blade.stiffness;
    let mut rates = [[Vec3::ZERO; 3]; 3];
    let mut below = [Vec3::ZERO; 3];
    for i in 0..3 {
        let edge = p.points[i + 1] - p.points[i];
        let (group, _) = blade.bend_group(i);
        let swing = (Vec3::Y.cross(edge)) * (k[2] / k[i]);
        let bend = (p.w[i].cross(edge)) * bend_share(blade, i, angle[group], pressed);
        below[0] += swing;
        if group == BEND_A {
            below[1] += bend;
        } else {
            below[2] += bend;
        }
        rates[i] = below;
    }
    rates
}

/// The motions a contact moves: swing, bend A, bend B.
const MOVED: [usize; 3] = [SWING, BEND_A, BEND_B];

/// One point to push out: how deep, along which normal, which sample, and
/// the velocity of the surface it touches.
struct Violation {
    depth: f32,
    normal: Vec3,
    sample: usize,
    surface_velocity: Vec3,
    ground: bool,
}

fn sample_point(p: &Pose, w: &[f32; 4]) -> Vec3 {
    p.points[0] * w[0] + p.points[1] * w[1] + p.points[2] * w[2] + p.points[3] * w[3]
}

/// The point to push out next: the lowest point below the ground if there
/// is one (no collider may push a blade through the ground), else the
/// deepest point inside any of `colliders`.
fn deepest(p: &Pose, colliders: &[ColliderState]) -> Option<Violation> {
    let mut found: Option<Violation> = None;
    for (s, w) in SAMPLES.iter().enumerate() {
        let y = sample_point(p, w).y;
        if y < 0.0 && found.as_ref().is_none_or(|f| -y > f.depth) {
            found = Some(Violation {
                depth: -y,
                normal: Vec3::Y,
                sample: s,
                surface_velocity: Vec3::ZERO,
                ground: true,
            });
        }
    }
    if found.is_some() {
        return found;
    }
    for c in colliders {
        for (s, w) in SAMPLES.iter().enumerate() {
            let (d, n) = c.distance(sample_point(p, w));
            if d < 0.0 && found.as_ref().is_none_or(|f| -d > f.depth) {
                found = Some(Violation {
                    depth: -d,
                    normal: n,
                    sample: s,
                    surface_velocity: c.velocity,
                    ground: false,
                });
            }
        }
    }
    found
}

/// Resolves the blade's contacts with `colliders` after a substep (the
/// model in this file's header): up to CONTACT_ITERATIONS projections of
/// the deepest point, each with its velocity impulse. Returns whether any
/// collider was touched; `current` is the pose of the state it leaves.
pub fn resolve(
    blade: &GrassBlade,
    state: &mut GrassState,
    pressed: f32,
    current: &mut Pose,
    colliders: &[ColliderState],
) -> bool {
    let mut touched = false;
    let moved = if blade.split() < 3 { 3 } else { 2 };
    for _ in 0..CONTACT_ITERATIONS {
        let Some(v) = deepest(current, colliders) else {
            break;
        };
        touched |= !v.ground;
        let rates = point_rates(blade, state.angle, pressed, current);
        let w = SAMPLES[v.sample];
        let mut g = [0.0f32; 3];
        let mut denominator = 0.0f32;
        for (j, gj) in g.iter_mut().enumerate().take(moved) {
            let rate = rates[0][j] * w[1] + rates[1][j] * w[2] + rates[2][j] * w[3];
            *gj = v.normal.dot(rate);
            denominator += *gj * *gj / blade.inertia[MOVED[j]];
        }
        if denominator <= 1e-12 {
            break;
        }
        // Position: the smallest inertia-weighted change of the angles that
        // moves the point out by its depth (and the slop), linearised.
        let lambda = (v.depth + CONTACT_SLOP) / denominator;
        for j in 0..moved {
            let m = MOVED[j];
            let change = (g[j] / blade.inertia[m] * lambda).clamp(-MAX_CORRECTION, MAX_CORRECTION);
            state.angle[m] = (state.angle[m] + change).clamp(-MAX_ANGLE, MAX_ANGLE);
        }
        // Velocity: the contact torque's impulse, inelastic along the normal.
        let mut normal_speed = 0.0f32;
        for j in 0..moved {
            normal_speed += g[j] * state.velocity[MOVED[j]];
        }
        let surface_speed = v.normal.dot(v.surface_velocity);
        if normal_speed < surface_speed {
            let impulse = (surface_speed - normal_speed) / denominator;
            for j in 0..moved {
                let m = MOVED[j];
                state.velocity[m] += g[j] / blade.inertia[m] * impulse;
            }
        }
        *current = pressed_pose(blade, state.angle, pressed);
    }
    touched
}

/// A blade's pressed state as the grass step keeps it (src/interface/defs.rs):
/// the pressed state its last step used (and its pose shows) and whether
/// that step touched a collider. The next step starts from `Press::next`,
/// so a step's pose, contacts and drawn shape all use one value.
pub use crate::interface::Press;

impl Press {
    /// The pressed state of the next step of `dt`: raised by dt /
    /// PRESS_RISE_TIME (up to 1) if the last step touched a collider, else
    /// decayed by `decay` = exp(-dt / PRESS_DECAY_TIME).
    pub fn next(self, dt: f32, decay: f32) -> f32 {
        if self.touched != 0.0 {
            (self.pressed + dt / PRESS_RISE_TIME).min(1.0)
        } else {
            self.pressed * decay
        }
    }
}

/// The time at the end of step `steps_done` (0-based) of `dt`: where the
/// colliders stand while the step resolves its contacts, on the CPU and
/// the GPU alike.
pub fn step_end_time(steps_done: u64, dt: f32) -> f32 {
    ((steps_done + 1) as f64 * dt as f64) as f32
}

/// The decay factor of the pressed state over one step of `dt`.
pub fn press_decay(dt: f32) -> f32 {
    (-dt / PRESS_DECAY_TIME).exp()
}

/// `grass::step` for a blade in the pressed state `pressed` that may touch
/// `colliders`: each substep's contacts resolved after the ground's.
/// Returns whether a collider was touched.
pub fn step_touching(
    blade: &GrassBlade,
    state: &mut GrassState,
    wind: Vec3,
    dt: f32,
    substeps: u32,
    pressed: f32,
    colliders: &[ColliderState],
) -> bool {
    step_with(
        blade,
        state,
        wind,
        dt,
        substeps,
        pressed,
        |state, current| {
            // A pressed blade's shares change between steps, which can lay part
            // of it into the ground: the projection puts the ground first.
            (!colliders.is_empty() || pressed != 0.0)
                && resolve(blade, state, pressed, current, colliders)
        },
    )
}

/// The colliders a blade rooted at `root` could touch, in order.
pub fn near_blade(states: &[ColliderState], root: Vec3, reach: f32) -> Vec<ColliderState> {
    states
        .iter()
        .filter(|c| c.near(root, reach))
        .copied()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn the_samples_are_points_of_the_drawn_curve() {
        for w in SAMPLES {
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6, "{w:?}");
        }
        assert_eq!(bernstein(0.5), [0.125, 0.375, 0.375, 0.125]);
    }

    #[test]
    fn the_pressed_state_decays_and_softens_the_restoring_force() {
        use crate::model::grass::{give, PRESS_SOFTENING};
        assert_eq!(give(0.0), 1.0);
        assert!((give(1.0) - (1.0 - PRESS_SOFTENING)).abs() < 1e-7);
        let decay = press_decay(0.5);
        let touched = |pressed| Press {
            pressed,
            touched: 1.0,
        };
        let mut pressed = touched(0.0).next(PRESS_RISE_TIME / 2.0, decay);
        assert!((pressed - 0.5).abs() < 1e-6, "{pressed}");
        pressed = touched(0.3).next(PRESS_RISE_TIME, decay);
        assert_eq!(pressed, 1.0);
        for _ in 0..4 {
            pressed = Press {
                pressed,
                touched: 0.0,
            }
            .next(0.5, decay);
        }
        // Two seconds at a one-second time constant.
        assert!((pressed - (-2.0f32 / PRESS_DECAY_TIME).exp()).abs() < 1e-6);
    }
}
