//! Turbulence everywhere (ours, beyond the paper): a fluctuating,
//! divergence-free wind the solver's mean wind carries, statistically the
//! same all over the grid and alive far from any inflow.
//!
//! A kinematic simulation (Kraichnan 1970; Fung, Hunt, Malik and Perkins,
//! J. Fluid Mech. 236, 1992): a sum of random Fourier modes whose energies
//! follow the von Karman spectrum of the set intensity and integral length
//! scale, each moved with the inflow's mean velocity (Taylor's frozen
//! turbulence) and changing at its own rate while it goes. Each mode is the
//! discrete curl of a vector potential on the grid's staggered faces
//! (its wavenumber replaced by the difference quotient's), so what the faces
//! hold is divergence-free cell by cell, to rounding. The solver steps the
//! mean wind alone: each step takes off what the last one added and adds
//! the field at the step's end (`WindField::step`). docs/method.md says why
//! this method and what it leaves out.

use glam::{DVec3, UVec3, Vec3};
use rand::{Rng, SeedableRng};

use crate::interface::TurbulenceMode;

/// `wind.turbulence` of a scene.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Turbulence {
    /// sigma_u / U: the standard deviation of each horizontal component
    /// over the reference speed.
    pub intensity: f32,
    /// The integral length scale L (m) of the velocity along the wind.
    pub length_scale: f32,
    /// Draws the modes: the same seed, the same turbulence.
    #[serde(default)]
    pub seed: u32,
    /// The reference speed U (m/s) the intensity is relative to: the
    /// inflow's speed when absent; needed without an inflow.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f32>,
}

/// Fourier modes in the field: enough for patches without visible
/// repetition, few enough for a face to sum them every step.
pub const MODES: usize = 48;

/// lambda of the modes' own rate, omega = lambda sqrt(k^3 E(k)) (Fung et
/// al. 1992 take 0.4-1): eddies change while they are carried, over about
/// their turnover time.
const UNSTEADINESS: f64 = 0.5;

/// The von Karman spectrum's peak k_e times the integral length scale:
/// L = sqrt(pi) Gamma(5/6) / Gamma(1/3) / k_e.
const PEAK_TIMES_LENGTH: f64 = 0.746_834;

/// The lowest wavenumber drawn, in units of k_e: below it the spectrum
/// (rising as k^4) holds under 1e-4 of the energy.
const LOWEST: f64 = 0.1;

/// One Fourier mode.
#[derive(Clone, Copy, Debug)]
struct Mode {
    /// Wavenumber (rad/m); along a mirrored axis a whole number of half
    /// waves across the grid, 0 or more.
    k: DVec3,
    /// What the mode adds to a face of each axis at phase 0 (m/s).
    amplitude: Vec3,
    /// Phase at t = 0 at the grid's corner (rad).
    phase: f64,
    /// Its own rate (rad/s).
    omega: f64,
}

/// The modes of one scene's turbulence on one grid (for sigma = 1 m/s),
/// and how far the mean wind has carried them and how far they have
/// changed: integrals over the steps taken, so that a wind that changes
/// speed or heading (the viewer's keys) moves the patches on without a
/// jump.
#[derive(Clone, Debug)]
pub struct TurbulenceField {
    modes: Vec<Mode>,
    /// Bit a: the grid's two sides across axis a are walls, and each mode
    /// is paired with its mirror images across them (`at`).
    mirrored: u32,
    cell: Vec3,
    /// The integral of the convection velocity (m).
    drift: DVec3,
    /// The integral of sigma (m): each mode's own rate is sigma times its
    /// rate at sigma = 1.
    clock: f64,
}

impl TurbulenceField {
    /// Whether the modes are mirrored across the grid's two sides across
    /// `axis` (their normal component vanishing there).
    pub fn is_mirrored(&self, axis: usize) -> bool {
        self.mirrored & (1 << axis) != 0
    }

    /// The modes of `turbulence` on a grid of `cells` cells of `cell`
    /// metres whose sides across each axis with `walls` set hold no flow
    /// through them, for a standard deviation of 1 m/s (`records` scales
    /// them): wavenumbers log-spaced from 0.1 k_e to the Nyquist
    /// wavenumber of the grid's coarsest axis (none aliases), directions
    /// uniform on the sphere, each polarised at random across its
    /// wavenumber (so divergence-free), energies E(k) dk of the von Karman
    /// spectrum E ~ (k/k_e)^4 / (1 + (k/k_e)^2)^(17/6). Across walls a
    /// wavenumber is rounded to a whole number of half waves across the
    /// grid and the mode paired with its mirror images (the normal
    /// component then vanishes on both walls: the modes of a channel). The
    /// whole is scaled so that the horizontal components' variance over the
    /// grid's cells is 1 (the resolved modes carry it all).
    pub fn new(turbulence: &Turbulence, cells: UVec3, cell: Vec3, walls: [bool; 3]) -> Self {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(0x7475_7262 ^ turbulence.seed as u64);
        let h = cell.as_dvec3();
        let size = cells.as_dvec3() * h;
        let k_e = PEAK_TIMES_LENGTH / turbulence.length_scale as f64;
        let k_lo = LOWEST * k_e;
        let k_hi = (std::f64::consts::PI / h.max_element()).max(k_lo * 1.01);
        let span = (k_hi / k_lo).ln();
        let spectrum = |k: f64| {
            let r = k / k_e;
            r.powi(4) / (1.0 + r * r).powf(17.0 / 6.0)
        };
        let mirrored = (0..3).filter(|&a| walls[a]).map(|a| 1u32 << a).sum();
        let wavenumber_at = |n: usize| k_lo * (span * (n as f64 + 0.5) / MODES as f64).exp();
        // The spectrum's integral over the shells: E(k) = 1.5 spectrum(k)
        // / it is the von Karman spectrum of sigma = 1 (its integral is the
        // kinetic energy, 3/2 sigma^2).
        let integral: f64 = (0..MODES)
            .map(|n| {
                let k = wavenumber_at(n);
                spectrum(k) * span / MODES as f64 * k
            })
            .sum();
        let modes: Vec<Mode> = (0..MODES)
            .map(|n| {
                let k = wavenumber_at(n);
                let shell = span / MODES as f64 * k;
                let weight = spectrum(k) * shell;
                let mut wavenumber = unit_on_sphere(&mut rng) * k;
                for a in (0..3).filter(|&a| walls[a]) {
                    let half_wave = std::f64::consts::PI / size[a];
                    wavenumber[a] = (wavenumber[a].abs() / half_wave).round() * half_wave;
                }
                let (e1, e2) = wavenumber
                    .try_normalize()
                    .unwrap_or(DVec3::X)
                    .any_orthonormal_pair();
                let angle = rng.random::<f64>() * std::f64::consts::TAU;
                let a = (e1 * angle.cos() + e2 * angle.sin()) * weight.sqrt();
                let phase = rng.random::<f64>() * std::f64::consts::TAU;
                // Its rate at sigma = 1 from E(k) per wavenumber.
                let omega = UNSTEADINESS * (k.powi(3) * 1.5 * spectrum(k) / integral).sqrt();
                Mode {
                    k: wavenumber,
                    amplitude: face_amplitude(wavenumber, a, h),
                    phase,
                    omega,
                }
            })
            .collect();
        let mut field = Self {
            modes,
            mirrored,
            cell,
            drift: DVec3::ZERO,
            clock: 0.0,
        };
        // The horizontal components' variance over (at most about 20,000
        // of) the cells' centres, made 1: a few dozen random modes leave
        // the field a draw away from any analytic mean.
        let records = field.records(1.0);
        let stride = ((cells.as_dvec3().element_product() / 20_000.0)
            .cbrt()
            .ceil() as u32)
            .max(1);
        let (mut sum, mut count) = (0.0f64, 0usize);
        for i in (0..cells.x).step_by(stride as usize) {
            for j in (0..cells.y).step_by(stride as usize) {
                for k in (0..cells.z).step_by(stride as usize) {
                    let q = UVec3::new(2 * i + 1, 2 * j + 1, 2 * k + 1);
                    sum += (field.at(&records, 0, q) as f64).powi(2)
                        + (field.at(&records, 2, q) as f64).powi(2);
                    count += 2;
                }
            }
        }
        let scale = (count as f64 / sum.max(f64::MIN_POSITIVE)).sqrt();
        for m in &mut field.modes {
            m.amplitude *= scale as f32;
        }
        field
    }

    /// The half-cell point of face `f` of component `axis`: 2 f along the
    /// axis, 2 f + 1 across it.
    pub fn face_point(axis: usize, f: [u32; 3]) -> UVec3 {
        let mut q = UVec3::from(f) * 2 + 1;
        q[axis] -= 1;
        q
    }

    /// Component `axis` of the field `records` describe at half-cell point
    /// `q` (at q h / 2 from the grid's minimum corner), as
    /// glsl/wind/turbulence.comp sums it. A mode a cos(k . x + theta)
    /// paired with its mirror images across the walls of the axes m in
    /// `mirrored` is, for each component, cos(theta') (or -sin(theta') for
    /// the component across a mirrored axis) times, per mirrored axis m,
    /// sin(k_m x_m) for the component across it and cos(k_m x_m) for the
    /// others, theta' the phase along the axes not mirrored: the normal
    /// component is zero on both walls.
    pub fn at(&self, records: &[TurbulenceMode], axis: usize, q: UVec3) -> f32 {
        let x = q.as_vec3() * 0.5 * self.cell;
        let mut u = 0.0;
        for m in records {
            let [kx, ky, kz, phase] = m.wavenumber_phase;
            let k = [kx, ky, kz];
            let mut theta = phase;
            for a in 0..3 {
                if m.mirrored & (1 << a) == 0 {
                    theta += k[a] * x[a];
                }
            }
            let mut f = if m.mirrored & (1 << axis) != 0 {
                -theta.sin()
            } else {
                theta.cos()
            };
            for a in 0..3 {
                if m.mirrored & (1 << a) != 0 {
                    f *= if a == axis {
                        (k[a] * x[a]).sin()
                    } else {
                        (k[a] * x[a]).cos()
                    };
                }
            }
            u += m.amplitude[axis] * f;
        }
        u
    }

    /// One step of `dt` (s): the modes carried with `convection` (m/s)
    /// and changed at the rate of `sigma` (m/s).
    pub fn advance(&mut self, convection: Vec3, sigma: f32, dt: f32) {
        self.drift += convection.as_dvec3() * dt as f64;
        self.clock += sigma as f64 * dt as f64;
    }

    /// The grid's corner moved by `d` (m): the modes' phases follow, so
    /// that the field stays where it is in the world.
    pub fn move_corner(&mut self, d: Vec3) {
        self.drift -= d.as_dvec3();
    }

    /// The modes as the GPU reads them now, for a standard deviation of
    /// `sigma` (m/s): the phase theta_n = phi_n + omega_n int(sigma dt) -
    /// k_n . int(U dt) (along the axes not mirrored), in double precision,
    /// reduced to [0, 2 pi).
    pub fn records(&self, sigma: f32) -> Vec<TurbulenceMode> {
        self.modes
            .iter()
            .map(|m| {
                let carried: f64 = (0..3)
                    .filter(|&a| self.mirrored & (1 << a) == 0)
                    .map(|a| m.k[a] * self.drift[a])
                    .sum();
                let phase =
                    (m.phase + m.omega * self.clock - carried).rem_euclid(std::f64::consts::TAU);
                TurbulenceMode {
                    wavenumber_phase: m.k.as_vec3().extend(phase as f32).to_array(),
                    amplitude: (m.amplitude * sigma).to_array(),
                    mirrored: self.mirrored,
                }
            })
            .collect()
    }
}

/// A point uniform on the unit sphere.
fn unit_on_sphere(rng: &mut impl Rng) -> DVec3 {
    let y = rng.random::<f64>() * 2.0 - 1.0;
    let angle = rng.random::<f64>() * std::f64::consts::TAU;
    let r = (1.0 - y * y).max(0.0).sqrt();
    DVec3::new(r * angle.cos(), y, r * angle.sin())
}

/// The velocity amplitude `a` (across `k`) as the staggered faces hold it:
/// the mode is the curl of the vector potential psi = k x a / |k|^2 sin
/// (see below), and the faces take the curl's difference quotients, whose
/// wavenumber along each axis is k~ = 2 sin(k h / 2) / h: the faces hold
/// -k~ x (k x a) / |k|^2 cos(theta), which is `a` when k~ = k and whose
/// discrete divergence, i k~ . (k~ x ...), is zero.
fn face_amplitude(k: DVec3, a: DVec3, h: DVec3) -> Vec3 {
    let modified = DVec3::new(
        2.0 * (0.5 * k.x * h.x).sin() / h.x,
        2.0 * (0.5 * k.y * h.y).sin() / h.y,
        2.0 * (0.5 * k.z * h.z).sin() / h.z,
    );
    (-modified.cross(k.cross(a)) / k.length_squared()).as_vec3()
}
