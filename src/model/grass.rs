//! Grass dynamics, the CPU reference (paper section 4; docs/method.md section 4):
//! swinging, bending and twisting of every blade, driven by the wind at its
//! tip. glsl/grass/dynamics.glsl is the same model, line for line, in f32;
//! tests/grass_gpu.rs compares the two.
//!
//! The reading this project takes (docs/method.md: "ours"):
//! - each motion keeps one scalar angle and angular velocity per blade (two
//!   bending angles for a drooping blade, one per slope group);
//! - forces are the paper's vectors W + R, the torque is lever x F taken
//!   along the motion's axis, damping is the torque -c omega;
//! - the shape is rebuilt every step from the rest shape: edge i bends by
//!   theta_i = (k_tip / k_i) theta (eq. 12) about E_w and swings by its own
//!   (k_tip / k_i) share of the swing angle about the ground normal, root to
//!   tip, so the root and every edge length stay exact; twisting turns only
//!   the width vectors;
//! - the swing's lever and inertia follow from that motion by virtual work
//!   (`swing_lever`, `swing_inertia`), so its torque, its inertia and its
//!   shape describe one and the same rigid-segment motion.

use glam::Vec3;

use crate::error::{Error, Result};
use crate::model::blade::{Blade, BladeVertex, UP};

/// The motions, in the order of every per-motion vec4, and the fold and
/// wind guards: written once for both sides (src/interface).
pub use crate::interface::{BEND_A, BEND_B, MAX_ANGLE, MAX_WIND_SPEED, SWING, TWIST};

/// Substeps per simulation step may not pass this: a blade that would need
/// more is refused with advice instead of slowing every frame.
pub const MAX_SUBSTEPS: u32 = 64;

/// Stability margin: each substep h keeps h * (omega_0 + c / I) <= this,
/// well inside symplectic Euler's bound (h^2 omega_0^2 + 2 h c / I < 4),
/// with room for the stiffness the wind itself adds.
const STEP_MARGIN: f64 = 0.5;

/// The physical parameters of one blade, drawn by the field generator from
/// the scene's ranges (`scene::GrassDynamics`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BladePhysics {
    /// Mass of each of the three edges (kg).
    pub edge_mass: f32,
    /// Drag coefficient sigma of W = S sigma v (N s / m^3).
    pub sigma: f32,
    /// Stiffness k_tip of the tip edge (N / rad).
    pub tip_stiffness: f32,
    /// k_root / k_tip; the middle edge sits geometrically between (>= 1).
    pub stiffness_ratio: f32,
    /// Damping as a fraction of critical damping; c of each motion is
    /// 2 zeta sqrt(k_eff I).
    pub damping_ratio: f32,
}

impl BladePhysics {
    /// One line per problem, naming the parameter and the allowed range.
    /// The first parameter out of its range: (name, value, allowed range).
    pub fn first_invalid(&self) -> Option<(&'static str, f32, &'static str)> {
        let checks: [(&str, f32, bool, &str); 5] = [
            ("edge_mass", self.edge_mass, self.edge_mass > 0.0, "> 0 kg"),
            ("sigma", self.sigma, self.sigma >= 0.0, ">= 0"),
            (
                "tip_stiffness",
                self.tip_stiffness,
                self.tip_stiffness > 0.0,
                "> 0 N/rad",
            ),
            (
                "stiffness_ratio",
                self.stiffness_ratio,
                self.stiffness_ratio >= 1.0,
                ">= 1 (the root is stiffest)",
            ),
            (
                "damping_ratio",
                self.damping_ratio,
                (0.0..=10.0).contains(&self.damping_ratio),
                "0..=10",
            ),
        ];
        checks
            .into_iter()
            .find(|&(_, value, ok, _)| !(value.is_finite() && ok))
            .map(|(name, value, _, allowed)| (name, value, allowed))
    }

    pub fn validate(&self) -> Result<()> {
        match self.first_invalid() {
            Some((name, value, allowed)) => Err(Error::InvalidInput(format!(
                "grass dynamics: {name} {value} is not allowed, use {allowed}"
            ))),
            None => Ok(()),
        }
    }
}

/// One blade as the grass kernel reads it, and its state: angle and angular
/// velocity of each motion (src/interface/defs.rs).
pub use crate::interface::{GrassBlade, GrassState};

/// The current shape of a blade, rebuilt from the rest shape and the angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Control points P0 (root) .. P3 (tip).
    pub points: [Vec3; 4],
    /// E_e of each edge (unit).
    pub e: [Vec3; 3],
    /// E_w of each edge: the rest E_w swung by the edge's share of the
    /// swing (bending turns the edge about it).
    pub w: [Vec3; 3],
    /// E_n = E_w x E_e of each edge.
    pub n: [Vec3; 3],
    /// The twisted width direction E_w_local of each edge.
    pub w_local: [Vec3; 3],
}

impl GrassBlade {
    /// Derives the kernel's record from a blade's rest shape and physics.
    pub fn new(blade: &Blade, physics: &BladePhysics) -> Result<Self> {
        physics.validate()?;
        let lengths = blade.edge_lengths();
        let too_short = |l: f32| !l.is_finite() || l <= 1e-5;
        if lengths.into_iter().any(too_short)
            || blade.half_width.is_nan()
            || blade.half_width <= 0.0
        {
            return Err(Error::InvalidInput(format!(
                "a blade has edge lengths {lengths:?} m and half width {} m; every edge must be \
                 longer than 0.01 mm and the blade wider than zero",
                blade.half_width
            )));
        }
        // Bending groups (paper Fig. 7): a new group starts at the first
        // edge whose slope sign differs from the root edge's.
        let rising = |i: usize| blade.rest[i + 1].y >= blade.rest[i].y;
        let split = (1..3).find(|&i| rising(i) != rising(0)).unwrap_or(3);
        let r = physics.stiffness_ratio as f64;
        let k_tip = physics.tip_stiffness as f64;
        // Stiffness grows toward the root: k_2 = k_tip, k_1 = k_tip sqrt(r), k_0 = k_tip r.
        let k: [f64; 3] = std::array::from_fn(|i| k_tip * r.powf((2 - i) as f64 / 2.0));
        let len = lengths.map(|l| l as f64);
        let hw = blade.half_width as f64;
        let m = physics.edge_mass as f64;
        let sigma = physics.sigma as f64;
        let area = |edges: std::ops::Range<usize>| len[edges].iter().sum::<f64>() * 2.0 * hw;

        let tip_a = split - 1;
        let groups = [(0..split, tip_a), (split..3, 2)];
        let mut drag = [0.0f64; 4];
        let mut inertia = [1.0f64; 4];
        // Swinging: each edge about the ground normal by its eq. 12 share.
        drag[SWING] = sigma * area(0..3);
        let rest_edges: [Vec3; 3] = std::array::from_fn(|i| blade.rest[i + 1] - blade.rest[i]);
        inertia[SWING] = swing_inertia(&rest_edges, swing_shares(&k), m, hw);
        // Bending: each group about E_w, lever its local tip edge.
        for (motion, (edges, tip)) in [BEND_A, BEND_B].into_iter().zip(groups) {
            if edges.is_empty() {
                continue;
            }
            drag[motion] = sigma * area(edges.clone());
            inertia[motion] = edges.len() as f64 * m * len[tip] * len[tip];
        }
        // Twisting: the blade face about E_e, lever the half width.
        drag[TWIST] = sigma * area(0..3);
        inertia[TWIST] = 3.0 * m * hw * hw;

        let f = |v: [f64; 4]| v.map(|x| x as f32);
        let mut out = Self {
            rest_root: blade.rest[0].to_array(),
            blade_rand: blade.rand,
            rest_1: blade.rest[1].to_array(),
            ground_normal_x: blade.ground.x,
            rest_2: blade.rest[2].to_array(),
            ground_curvature: blade.ground_curvature,
            rest_tip: blade.rest[3].to_array(),
            ground_normal_z: blade.ground.z,
            width_dir: blade.width_dir.to_array(),
            half_width: blade.half_width,
            stiffness: [k[0] as f32, k[1] as f32, k[2] as f32],
            group_b_edge: split as u32,
            drag: f(drag),
            inertia: f(inertia),
            damping: [0.0; 4],
        };
        // c = 2 zeta sqrt(k_eff I) per motion.
        let zeta = physics.damping_ratio as f64;
        let k_eff = out.k_eff();
        out.damping = std::array::from_fn(|i| {
            (2.0 * zeta * (k_eff[i] as f64 * out.inertia[i] as f64).sqrt()) as f32
        });
        Ok(out)
    }

    /// The ground's upward unit normal at the root (`Blade::ground`): its
    /// x and z are kept, its y follows (upward: positive).
    pub fn ground_normal(&self) -> Vec3 {
        let (x, z) = (self.ground_normal_x, self.ground_normal_z);
        Vec3::new(x, (1.0 - x * x - z * z).max(0.0).sqrt(), z)
    }

    /// Rest control point P_i.
    pub fn rest_point(&self, i: usize) -> Vec3 {
        Vec3::from([self.rest_root, self.rest_1, self.rest_2, self.rest_tip][i])
    }

    /// Rest E_w (unit, horizontal).
    pub fn width_dir(&self) -> Vec3 {
        Vec3::from(self.width_dir)
    }

    /// First edge of bending group B; 3 when the blade has one group.
    pub fn split(&self) -> usize {
        self.group_b_edge as usize
    }

    /// Which bending motion edge `i` belongs to, and its group's local tip edge.
    pub fn bend_group(&self, i: usize) -> (usize, usize) {
        let split = self.split();
        if i < split {
            (BEND_A, split - 1)
        } else {
            (BEND_B, 2)
        }
    }

    /// Small-angle restoring torque per radian of each motion (the k_eff of
    /// I theta'' = -k_eff theta - c theta'): the lever length times the
    /// stiffness of the edge the restoration acts on.
    pub fn k_eff(&self) -> [f32; 4] {
        let rest_edge = |i: usize| self.rest_point(i + 1) - self.rest_point(i);
        let (_, tip_a) = self.bend_group(0);
        let k = self.stiffness;
        [
            swing_lever(self, 0.0).length() * k[2],
            rest_edge(tip_a).length() * k[tip_a],
            if self.split() < 3 {
                rest_edge(2).length() * k[2]
            } else {
                0.0
            },
            self.half_width * k[2],
        ]
    }

    /// The natural frequency of `motion` (Hz): I theta'' = -k_eff theta -
    /// c theta' rings at sqrt(k_eff / I) sqrt(1 - zeta^2) / 2 pi, zeta =
    /// c / 2 sqrt(k_eff I) (none when overdamped: 0). Small angles, still
    /// air: the wind's own stiffness and the restoring force's fading at
    /// large angles are left out.
    pub fn natural_frequency_hz(&self, motion: usize) -> f64 {
        let (k, i, c) = (
            self.k_eff()[motion] as f64,
            self.inertia[motion] as f64,
            self.damping[motion] as f64,
        );
        if k <= 0.0 || i <= 0.0 {
            return 0.0;
        }
        let zeta = c / (2.0 * (k * i).sqrt());
        (k / i).sqrt() * (1.0 - zeta * zeta).max(0.0).sqrt() / std::f64::consts::TAU
    }

    /// The fastest rate of any of its motions, sqrt(k_eff / I) + c / I (1/s).
    pub fn stiffest_rate(&self) -> f64 {
        let k = self.k_eff();
        (0..4)
            .filter(|&m| m != BEND_B || self.split() < 3)
            .map(|m| {
                let i = self.inertia[m] as f64;
                (k[m] as f64 / i).sqrt() + self.damping[m] as f64 / i
            })
            .fold(0.0, f64::max)
    }
}

/// Substeps each simulation step of `dt` needs so that explicit
/// (symplectic) Euler stays stable for every blade (docs/method.md: dt < 2 /
/// sqrt(k / I), with margin). Refuses blades that would need too many.
pub fn substeps(blades: &[GrassBlade], dt: f32) -> Result<u32> {
    let rate = blades
        .iter()
        .map(GrassBlade::stiffest_rate)
        .fold(0.0, f64::max);
    let n = (dt as f64 * rate / STEP_MARGIN).ceil().max(1.0);
    if !n.is_finite() || n > MAX_SUBSTEPS as f64 {
        return Err(Error::InvalidInput(format!(
            "the stiffest blade needs {n} substeps of a {dt} s simulation step (at most \
             {MAX_SUBSTEPS}); lower tip_stiffness or damping_ratio, raise edge_mass, or \
             shorten wind.dt"
        )));
    }
    Ok(n as u32)
}

/// v rotated by `angle` about the unit `axis` (Rodrigues). Written out so
/// that glsl/grass/dynamics.glsl does the same arithmetic.
pub fn rotate(v: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * (axis.dot(v) * (1.0 - c))
}

/// `v` normalised, or zero when it is too short to have a direction (the
/// paper's ds when a motion is at rest: R = 0, never a division by zero).
fn direction_or_zero(v: Vec3) -> Vec3 {
    let l = v.length();
    if l > 1e-7 {
        v / l
    } else {
        Vec3::ZERO
    }
}

fn normalize_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let l = v.length();
    if l > 1e-12 {
        v / l
    } else {
        fallback
    }
}

/// Eq. 12's shares k_tip / k_i of edges 0, 1, 2 (root to tip).
fn swing_shares(k: &[f64; 3]) -> [f64; 3] {
    k.map(|k_i| k[2] / k_i)
}

/// The horizontal part of a vector (its shadow on the ground plane).
fn flat(v: Vec3) -> Vec3 {
    Vec3::new(v.x, 0.0, v.z)
}

/// The swing's inertia about the ground normal, I = sum of m r^2 over the
/// blade, for the motion eq. 12 gives it: edge i turns by s_i theta about
/// the vertical through its lower end. Each edge is a uniform plate of mass
/// `m`, its length along the edge and `hw` either side of it, so a point at
/// fraction u along edge j and at width offset t moves by
/// dP/dtheta = UP x (sum over i < j of s_i h_i + u s_j h_j) + s_j t (UP x E_w)
/// (h: the edge's horizontal part). Integrated over u and t:
/// I = sum_j m (|A_j|^2 + A_j . B_j + |B_j|^2 / 3 + s_j^2 hw^2 / 3),
/// A_j = sum over i < j of s_i h_i, B_j = s_j h_j. The width term keeps it
/// above zero for an upright blade, whose edges have no horizontal part.
/// tests/grass_cpu.rs integrates the pose's own motion numerically and
/// finds the same.
fn swing_inertia(rest_edges: &[Vec3; 3], shares: [f64; 3], m: f64, hw: f64) -> f64 {
    let mut below = glam::DVec3::ZERO;
    let mut inertia = 0.0;
    for (edge, s) in rest_edges.iter().zip(shares) {
        let b = flat(*edge).as_dvec3() * s;
        inertia += m * (below.length_squared() + below.dot(b) + b.length_squared() / 3.0)
            + m * s * s * hw * hw / 3.0;
        below += b;
    }
    inertia
}

/// The swing's lever at swing angle `theta`: L = sum of s_i h_i(theta),
/// the edges' horizontal parts, each swung by its share s_i theta (eq. 12).
/// A force F at the tip does virtual work F . dP3/dtheta = (L x F) . UP,
/// so L is the lever of "torque = lever x F" for this motion; it is the
/// tip's P0P3 only when every edge turns alike. Rest edges, not bent ones:
/// bending does not feed back into the swing, so the motions stay apart.
pub fn swing_lever(blade: &GrassBlade, theta: f32) -> Vec3 {
    let k = blade.stiffness;
    (0..3)
        .map(|i| {
            let share = k[2] / k[i];
            let rest_edge = blade.rest_point(i + 1) - blade.rest_point(i);
            flat(rotate(rest_edge, UP, share * theta)) * share
        })
        .sum()
}

/// Rebuilds the blade from its rest shape and the motions' angles, root to
/// tip: edge i bends about the rest E_w by its share of its group's angle
/// and swings about the ground normal by its share of the swing angle
/// (eq. 12 for both), and its width direction twists about the edge by its
/// share of the twist.
pub fn pose(blade: &GrassBlade, angle: [f32; 4]) -> Pose {
    pressed_pose(blade, angle, 0.0)
}

/// The pressed blade's softening and the flat root edge's turn, written
/// once for both sides (src/interface).
pub use crate::interface::{MIN_FLAT_TURN, PRESS_SOFTENING};

/// The factor on the swing and bend restoring forces of a blade this
/// pressed (exactly 1 when it is not).
pub fn give(pressed: f32) -> f32 {
    1.0 - PRESS_SOFTENING * pressed
}

/// Edge i's share of the rising group's bending angle `theta` in a fully
/// pressed blade: the turn that lays edge i flat on the ground, toward the
/// side `theta` bends to, over the turn that lays the root edge flat. At
/// theta = that root turn the whole group lies on the ground, which eq. 12's
/// shares never allow (the root edge turns by a quarter of the tip's at the
/// shipped stiffness ratio, so it stands under a ball). Bending about E_w by
/// +theta turns an edge at elevation psi (in the plane of E_w x UP and UP)
/// down toward E_w x UP: psi - theta. A root edge within MIN_FLAT_TURN of
/// flat has nothing to lay down: `fallback` (eq. 12's share) then.
pub fn flat_share(blade: &GrassBlade, i: usize, theta: f32, fallback: f32) -> f32 {
    let w = blade.width_dir();
    let along = w.cross(UP);
    let turn = |j: usize| {
        let edge = blade.rest_point(j + 1) - blade.rest_point(j);
        let psi = edge.y.atan2(edge.dot(along));
        if theta >= 0.0 {
            psi
        } else {
            psi - std::f32::consts::PI
        }
    };
    let root = turn(0);
    if root.abs() < MIN_FLAT_TURN {
        return fallback;
    }
    turn(i) / root
}

/// Edge i's share of its group's bending angle `theta`: eq. 12's
/// k_tip / k_i, moved toward `flat_share` as the blade is pressed
/// (group A only; exactly eq. 12's when unpressed).
pub fn bend_share(blade: &GrassBlade, i: usize, theta: f32, pressed: f32) -> f32 {
    let (group, tip) = blade.bend_group(i);
    let share = blade.stiffness[tip] / blade.stiffness[i];
    if pressed == 0.0 || group != BEND_A {
        return share;
    }
    share + (flat_share(blade, i, theta, share) - share) * pressed
}

/// `pose` of a blade in the pressed state `pressed` (src/model/contact.rs):
/// its rising edges share the bending so that it lies down flat, a crushed
/// stem giving way at the root (exactly `pose` when it is 0).
pub fn pressed_pose(blade: &GrassBlade, angle: [f32; 4], pressed: f32) -> Pose {
    let w_rest = blade.width_dir();
    let k = blade.stiffness;
    let mut points = [blade.rest_point(0); 4];
    let mut e = [UP; 3];
    let mut w = [w_rest; 3];
    for i in 0..3 {
        let (group, _) = blade.bend_group(i);
        let bend = bend_share(blade, i, angle[group], pressed) * angle[group];
        let swing = k[2] / k[i] * angle[SWING];
        let rest_edge = blade.rest_point(i + 1) - blade.rest_point(i);
        let edge = rotate(rotate(rest_edge, w_rest, bend), UP, swing);
        points[i + 1] = points[i] + edge;
        e[i] = normalize_or(edge, UP);
        w[i] = rotate(w_rest, UP, swing);
    }
    let n: [Vec3; 3] = std::array::from_fn(|i| normalize_or(w[i].cross(e[i]), Vec3::X));
    let w_local: [Vec3; 3] =
        std::array::from_fn(|i| rotate(w[i], e[i], k[2] / k[i] * angle[TWIST]));
    Pose {
        points,
        e,
        w,
        n,
        w_local,
    }
}

/// The torque of each motion about its axis at `pose`: lever x (W + R)
/// along the axis, plus the damping torque -c omega.
pub fn torques(blade: &GrassBlade, pose: &Pose, state: &GrassState, wind: Vec3) -> [f32; 4] {
    pressed_torques(blade, pose, state, wind, 1.0)
}

/// `torques` of a blade whose swing and bend restoring forces are scaled by
/// `give` (`give`: 1 unless a collider pressed the blade).
pub fn pressed_torques(
    blade: &GrassBlade,
    pose: &Pose,
    state: &GrassState,
    wind: Vec3,
    give: f32,
) -> [f32; 4] {
    let angle = state.angle;
    let mut torque = [
        swing_torque(blade, pose, angle, wind, give),
        bend_torque(blade, pose, BEND_A, angle, wind, give),
        0.0,
        twist_torque(blade, pose, angle, wind),
    ];
    if blade.split() < 3 {
        torque[BEND_B] = bend_torque(blade, pose, BEND_B, angle, wind, give);
    }
    std::array::from_fn(|m| torque[m] - blade.damping[m] * state.velocity[m])
}

/// Swinging: the blade turns about the ground normal through its root,
/// edge i by its eq. 12 share of the angle.
/// W_S = S sigma (v . E_w) E_w (E_w of the tip edge, where the wind is
/// sampled), R_S = k_tip dtheta_s (G_static - G_cur) / |..| with G the
/// growth vector, P0P3 on the ground plane; both act at the tip, so the
/// lever is `swing_lever`. (Bending does not move the lever or G, so the
/// two motions stay separate.)
fn swing_torque(blade: &GrassBlade, pose: &Pose, angle: [f32; 4], wind: Vec3, give: f32) -> f32 {
    let theta = angle[SWING];
    let k = blade.stiffness;
    let swung_edge = |i: usize, theta: f32| {
        let rest_edge = blade.rest_point(i + 1) - blade.rest_point(i);
        flat(rotate(rest_edge, UP, k[2] / k[i] * theta))
    };
    let g_static: Vec3 = (0..3).map(|i| swung_edge(i, 0.0)).sum();
    let g_cur: Vec3 = (0..3).map(|i| swung_edge(i, theta)).sum();
    let w = pose.w[2];
    let force = w * (blade.drag[SWING] * wind.dot(w))
        + direction_or_zero(g_static - g_cur) * (k[2] * theta.abs() * give);
    swing_lever(blade, theta).cross(force).dot(UP)
}

/// Bending of one slope group: its local tip edge turns about E_w.
/// W_B = S sigma (v . E_n) E_n, R_B = k dtheta_b (E_e_static - E_e_cur) / |..|
/// with k the local tip edge's stiffness; lever: the local tip edge.
/// E_e_static is the rest edge swung by its share of the swing, so that
/// swinging never reads as bending.
fn bend_torque(
    blade: &GrassBlade,
    pose: &Pose,
    motion: usize,
    angle: [f32; 4],
    wind: Vec3,
    give: f32,
) -> f32 {
    let tip = if motion == BEND_A {
        blade.split() - 1
    } else {
        2
    };
    let theta = angle[motion];
    let rest_edge = blade.rest_point(tip + 1) - blade.rest_point(tip);
    let swing = blade.stiffness[2] / blade.stiffness[tip] * angle[SWING];
    let e_static = normalize_or(rotate(rest_edge, UP, swing), UP);
    let n = pose.n[tip];
    let lever = pose.points[tip + 1] - pose.points[tip];
    let force = n * (blade.drag[motion] * wind.dot(n))
        + direction_or_zero(e_static - pose.e[tip]) * (blade.stiffness[tip] * theta.abs() * give);
    lever.cross(force).dot(pose.w[tip])
}

/// Twisting: the face turns about the tip edge E_e, on E_w_local only, with
/// the untwisted E_w as its rest value, so bending never sees it.
/// W_T = S sigma (v . E_n_local) E_n_local, E_n_local = E_w_local x E_e;
/// R_T = k_tip dtheta_t (E_w - E_w_local) / |..|; lever: the half width
/// along E_w_local, on the side the wind blows toward (side = +-1). That
/// choice turns the face edge-on to the wind (less drag) whichever way E_w
/// points. The restoring force pulls that lever's end back toward its rest
/// place, side * hw * E_w, hence the side in R_T's direction too.
fn twist_torque(blade: &GrassBlade, pose: &Pose, angle: [f32; 4], wind: Vec3) -> f32 {
    let theta = angle[TWIST];
    let e = pose.e[2];
    let w_local = pose.w_local[2];
    let n_local = normalize_or(w_local.cross(e), pose.n[2]);
    let side = if wind.dot(w_local) < 0.0 { -1.0 } else { 1.0 };
    let force = n_local * (blade.drag[TWIST] * wind.dot(n_local))
        + direction_or_zero(pose.w[2] - w_local) * (side * blade.stiffness[2] * theta.abs());
    (w_local * (side * blade.half_width)).cross(force).dot(e)
}

/// The wind a blade feels: non-finite components count as calm air and the
/// speed is capped at `MAX_WIND_SPEED`, so a broken field cannot poison
/// the grass.
pub fn guard_wind(v: Vec3) -> Vec3 {
    if !v.is_finite() {
        return Vec3::ZERO;
    }
    let speed = v.length();
    if speed > MAX_WIND_SPEED {
        v * (MAX_WIND_SPEED / speed)
    } else {
        v
    }
}

/// One simulation step of `dt`, in `substeps` equal symplectic Euler
/// substeps: omega' = omega + (N / I) h, theta' = theta + omega' h, with the
/// damping torque in N taken at (omega + omega') / 2. The wind is sampled
/// once per step, at the tip, by the caller.
pub fn step(blade: &GrassBlade, state: &mut GrassState, wind: Vec3, dt: f32, substeps: u32) {
    step_with(blade, state, wind, dt, substeps, 0.0, |_, _| false);
}

/// `step` for a blade in the pressed state `pressed` (src/model/contact.rs):
/// its pressed pose, its swing and bend restoring forces scaled by `give`,
/// and `after_substep` called with the state and its pose after each
/// substep's ground contact (the colliders' contacts resolve there). Returns
/// whether any call of `after_substep` returned true.
pub fn step_with(
    blade: &GrassBlade,
    state: &mut GrassState,
    wind: Vec3,
    dt: f32,
    substeps: u32,
    pressed: f32,
    mut after_substep: impl FnMut(&mut GrassState, &mut Pose) -> bool,
) -> bool {
    let wind = guard_wind(wind);
    let h = dt / substeps as f32;
    let give = give(pressed);
    let mut current = pressed_pose(blade, state.angle, pressed);
    let mut touched = false;
    for _ in 0..substeps {
        let torque = pressed_torques(blade, &current, state, wind, give);
        let before = *state;
        #[allow(clippy::needless_range_loop)] // four parallel per-motion arrays
        for m in 0..4 {
            // Damping at the step's midpoint, (omega + omega') / 2: second
            // order like the rest of symplectic Euler, where an explicit
            // -c omega would shift the period by O(h) (2.3% for the twist at
            // the shipped dt).
            let undamped = torque[m] + blade.damping[m] * state.velocity[m];
            let a = 0.5 * h * blade.damping[m] / blade.inertia[m];
            let omega =
                (state.velocity[m] * (1.0 - a) + undamped / blade.inertia[m] * h) / (1.0 + a);
            let theta = state.angle[m] + omega * h;
            // The MAX_ANGLE guard: past it the motion stops there.
            if theta.abs() > MAX_ANGLE {
                state.angle[m] = MAX_ANGLE.copysign(theta);
                state.velocity[m] = 0.0;
            } else {
                state.angle[m] = theta;
                state.velocity[m] = omega;
            }
        }
        current = pressed_pose(blade, state.angle, pressed);
        if below_ground(blade, &current) {
            ground_contact(blade, state, &before);
            current = pressed_pose(blade, state.angle, pressed);
        }
        touched |= after_substep(state, &mut current);
    }
    touched
}

/// Whether a control point left the region over the ground at the root
/// (`Blade::ground_curvature`: the paraboloid over the tangent plane that
/// the ground within the blade's reach lies under; the plane y = 0 on flat
/// ground). The region is convex and the drawn curve lies in its control
/// points' hull, so it stays above the ground when they do.
pub fn below_ground(blade: &GrassBlade, pose: &Pose) -> bool {
    let (root, ground) = (blade.rest_point(0), blade.ground_normal());
    let c = blade.ground_curvature;
    pose.points[1..]
        .iter()
        .any(|&p| (p - root).dot(ground) < c * (p - root).length_squared())
}

/// Ground contact (ours; the paper has no ground): on flat ground only
/// bending lowers a point (swinging turns about the vertical, twisting
/// turns only the width), so a substep that would bend a blade into the
/// ground keeps its bending angles from `before` and stops them, an
/// inelastic contact like the MAX_ANGLE guard. On a slope swinging a bent
/// blade about the vertical carries its tip over higher or lower ground,
/// so there the swing is kept and stopped too. The blade lies on the
/// ground while the wind holds it there and rises when the restoring
/// force wins.
pub fn ground_contact(blade: &GrassBlade, state: &mut GrassState, before: &GrassState) {
    let motions: &[usize] = if blade.ground_normal() == UP {
        &[BEND_A, BEND_B]
    } else {
        &[SWING, BEND_A, BEND_B]
    };
    for &m in motions {
        state.angle[m] = before.angle[m];
        state.velocity[m] = 0.0;
    }
}

/// The four control points as the renderer draws them: positions from the
/// pose, width vectors from the twisted E_w_local of the edge ending at
/// each point (the root takes the root edge's), and the tip edge's angle
/// from rest (swing and bend) for the motion view.
pub fn vertices(blade: &GrassBlade, pose: &Pose) -> [BladeVertex; 4] {
    let rest_tip = normalize_or(blade.rest_point(3) - blade.rest_point(2), UP);
    // atan2 of sine and cosine: exact zero at rest, accurate when small.
    let displacement = rest_tip
        .cross(pose.e[2])
        .length()
        .atan2(rest_tip.dot(pose.e[2]));
    std::array::from_fn(|i| {
        let edge = i.max(1) - 1;
        BladeVertex {
            position: pose.points[i].to_array(),
            blade_rand: blade.blade_rand,
            half_width: (pose.w_local[edge] * blade.half_width).to_array(),
            displacement,
        }
    })
}

/// Blade-steps that ended with an angle at its `MAX_ANGLE` cap: motion the
/// model could not follow (docs/physics.md). Counted by the GPU kernel too.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CapCounts {
    /// Blade-steps simulated.
    pub blade_steps: u64,
    /// Those with any motion at its cap.
    pub at_cap: u64,
    /// Per motion: swing, bend (group A), bend (group B), twist.
    pub swing: u64,
    pub bend_a: u64,
    pub bend_b: u64,
    pub twist: u64,
}

impl CapCounts {
    /// Records one blade's state after a step.
    pub fn count(&mut self, state: &GrassState) {
        self.blade_steps += 1;
        let capped = state.angle.map(|a| a.abs() >= MAX_ANGLE);
        self.at_cap += capped.contains(&true) as u64;
        for (total, hit) in [
            &mut self.swing,
            &mut self.bend_a,
            &mut self.bend_b,
            &mut self.twist,
        ]
        .into_iter()
        .zip(capped)
        {
            *total += hit as u64;
        }
    }

    /// The share of blade-steps at a cap (0 before any step).
    pub fn fraction(&self) -> f64 {
        self.at_cap as f64 / self.blade_steps.max(1) as f64
    }
}
