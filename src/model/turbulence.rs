//! Turbulence everywhere (ours, beyond the paper): a fluctuating,
//! divergence-free wind the solver's mean wind carries, statistically the
//! same all over the grid and alive far from any inflow.
//!
//! A kinematic simulation (Kraichnan 1970; Fung, Hunt, Malik and Perkins,
//! J. Fluid Mech. 236, 1992): a sum of random Fourier modes whose energies
//! follow the von Karman spectrum of the set intensity and integral length
//! scale, each moved with the inflow's mean velocity (Taylor's frozen
//! turbulence), changing at its own rate while it goes, and drawn afresh
//! at the end of its life (`TurbulenceField`). Each mode is the
//! discrete curl of a vector potential on the grid's staggered faces
//! (its wavenumber replaced by the difference quotient's), so what the faces
//! hold is divergence-free cell by cell, to rounding. Modes finer than the
//! grid, down to the scene's finest wavelength, are summed at each blade's
//! tip instead (`subgrid_records`, `velocity_at`). The solver steps the
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
    /// The shortest wavelength (m) the blades feel: the modes finer than
    /// the wind grid holds, down to it, are summed at each blade's tip
    /// (`velocity_at`); absent: `FINEST_WAVELENGTH`. One as long as the
    /// grid's shortest wave (two of its largest cell sides) or longer
    /// leaves the grid's alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finest_wavelength: Option<f32>,
}

impl Turbulence {
    /// The shortest wavelength the blades feel (m).
    pub fn finest_wavelength(&self) -> f32 {
        self.finest_wavelength.unwrap_or(FINEST_WAVELENGTH)
    }
}

/// The shortest wavelength the blades feel unless a scene says (m): about
/// a blade's height. The wind drives a blade's resonance (about 1 Hz) with
/// waves of U / f_bend, 3 m at 3 m/s, finer than a 2 m grid's shortest
/// (4 m); waves under half a metre change along the blade itself.
pub const FINEST_WAVELENGTH: f32 = 0.5;

/// Fourier modes in the field: enough for patches without visible
/// repetition, few enough for a face to sum them every step.
pub const MODES: usize = 48;

/// Wavenumber shells: each holds two of the modes, whose lives overlap by
/// half of one (`TurbulenceField::records`).
const SHELLS: usize = MODES / 2;

/// Fourier modes finer than the grid, summed at each blade's tip rather
/// than on the faces (`TurbulenceField::subgrid_records`), when the
/// scene's finest wavelength is shorter than the grid's shortest wave.
pub const SUBGRID_MODES: usize = 16;

/// Their shells, log-spaced from the grid's Nyquist wavenumber to the
/// finest wavelength's.
const SUBGRID_SHELLS: usize = SUBGRID_MODES / 2;

/// lambda of the modes' own rate, omega = lambda sqrt(k^3 E(k)) (Fung et
/// al. 1992 take 0.4-1): eddies change while they are carried, over about
/// their turnover time.
const UNSTEADINESS: f64 = 0.5;

/// A mode's life in radians of its own rate: 0.5 / omega, one turnover
/// time 1 / sqrt(k^3 E(k)) (with lambda 0.5); then it is drawn anew. The
/// modes below the spectrum's peak, whose own rate falls as k^3.5, live as
/// long as the peak's.
const LIFE: f64 = 0.5;

/// The von Karman spectrum's peak k_e times the integral length scale:
/// L = sqrt(pi) Gamma(5/6) / Gamma(1/3) / k_e.
const PEAK_TIMES_LENGTH: f64 = 0.746_834;

/// The lowest wavenumber drawn, in units of k_e: below it the spectrum
/// (rising as k^4) holds under 1e-4 of the energy.
const LOWEST: f64 = 0.1;

/// Draws per mode that estimate a shell's mean horizontal variance, which
/// sets the field's scale (`TurbulenceField::new`).
const SCALE_DRAWS: u64 = 64;

/// One draw of a mode, for sigma = 1 m/s before the field's scale.
#[derive(Clone, Copy, Debug)]
struct Mode {
    /// Wavenumber (rad/m); along a mirrored axis a whole number of half
    /// waves across the grid, 0 or more.
    k: DVec3,
    /// What the mode adds to a face of each axis at phase 0 (m/s); a
    /// sub-grid mode's own velocity amplitude.
    amplitude: DVec3,
    /// Phase at t = 0 at the grid's corner (rad).
    phase: f64,
    /// Its own rate (rad per metre of `clock`).
    omega: f64,
}

/// One wavenumber shell: its modes' wavenumbers are drawn log-uniform in
/// it, and live `life`.
#[derive(Clone, Copy, Debug)]
struct Shell {
    k_lo: f64,
    k_hi: f64,
    /// A mode's life (metres of `clock`: seconds times sigma).
    life: f64,
    /// Where in its life the shell's first mode is at t = 0 (0-1): the
    /// shells are not renewed in step.
    offset: f64,
}

/// The modes of one scene's turbulence on one grid (for sigma = 1 m/s),
/// and how far the mean wind has carried them and how far they have
/// changed: integrals over the steps taken, so that a wind that changes
/// speed or heading (the viewer's keys) moves the patches on without a
/// jump.
///
/// The modes are renewed (as a synthetic-eddy method recycles its eddies:
/// Jarrin, Benhamadouche, Laurence and Prosser, Int. J. Heat Fluid Flow
/// 27, 2006): each is drawn afresh, wavenumber, direction, polarisation
/// and phase, at the end of its life, and weighed over its life by sin(pi
/// s), s its age over its life. The two modes of a shell are half a life
/// apart, so the shell's weights squared add to 1 at every instant: its
/// energy stays, its patches come and go. Over a record of a few lives
/// the field is a fresh draw of the spectrum, not one draw carried on, and
/// each mode's line in a point's spectrum is widened to the inverse of its
/// life.
#[derive(Clone, Debug)]
pub struct TurbulenceField {
    seed: u32,
    /// The grid's `SHELLS`, then the sub-grid's (none, or
    /// `SUBGRID_SHELLS`).
    shells: Vec<Shell>,
    spectrum: VonKarman,
    /// The draws' scale: the horizontal components' variance is 1 on
    /// average over draws and over the grid.
    scale: f64,
    /// The grid's size (m), for the half waves across its walls.
    size: DVec3,
    /// Bit a: the grid's two sides across axis a are walls, and each mode
    /// is paired with its mirror images across them (`at`).
    mirrored: u32,
    cell: Vec3,
    /// The integral of the convection velocity (m).
    drift: DVec3,
    /// The integral of sigma (m): each mode's own rate and life are sigma
    /// times their rate and life at sigma = 1.
    clock: f64,
}

/// The von Karman spectrum of sigma = 1 over the shells' wavenumbers.
#[derive(Clone, Copy, Debug)]
struct VonKarman {
    /// The peak k_e (rad/m).
    k_e: f64,
    /// The integral of `shape` over the shells' wavenumbers.
    integral: f64,
}

impl VonKarman {
    /// The spectrum's shape, (k/k_e)^4 / (1 + (k/k_e)^2)^(17/6).
    fn shape(k: f64, k_e: f64) -> f64 {
        let r = k / k_e;
        r.powi(4) / (1.0 + r * r).powf(17.0 / 6.0)
    }

    /// E(k) (m^3/s^2): its integral is the kinetic energy, 3/2 sigma^2.
    fn energy(&self, k: f64) -> f64 {
        1.5 * Self::shape(k, self.k_e) / self.integral
    }

    /// A mode's own rate at sigma = 1, omega = lambda sqrt(k^3 E(k)) (rad
    /// per metre of `clock`).
    fn rate(&self, k: f64) -> f64 {
        UNSTEADINESS * (k.powi(3) * self.energy(k)).sqrt()
    }
}

/// A 64-bit key of a seed, a mode and a generation (splitmix64's
/// finalizer over each in turn): each draw its own random stream.
fn draw_key(seed: u32, slot: u64, generation: i64) -> u64 {
    let mix = |mut z: u64| {
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let a = mix(0x7475_7262 ^ seed as u64);
    let b = mix(a ^ slot.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    mix(b ^ (generation as u64).wrapping_mul(0xd1b5_4a32_d192_ed03))
}

impl TurbulenceField {
    /// Whether the modes are mirrored across the grid's two sides across
    /// `axis` (their normal component vanishing there).
    pub fn is_mirrored(&self, axis: usize) -> bool {
        self.mirrored & (1 << axis) != 0
    }

    /// The axes the modes are mirrored across, bit a for axis a (every
    /// mode's `mirrored`).
    pub fn mirrored(&self) -> u32 {
        self.mirrored
    }

    /// The modes of `turbulence` on a grid of `cells` cells of `cell`
    /// metres whose sides across each axis with `walls` set hold no flow
    /// through them, for a standard deviation of 1 m/s (`records` scales
    /// them): wavenumber shells log-spaced from 0.1 k_e to the Nyquist
    /// wavenumber of the grid's coarsest axis (none aliases), each mode's
    /// wavenumber drawn log-uniform in its shell, its direction uniform on
    /// the sphere, polarised at random across its wavenumber (so
    /// divergence-free), its energy E(k) dk of the von Karman spectrum E ~
    /// (k/k_e)^4 / (1 + (k/k_e)^2)^(17/6). Where the scene's finest
    /// wavelength is shorter than the grid's shortest wave, `SUBGRID_MODES`
    /// more in shells on from the Nyquist wavenumber to it, which the grass
    /// sums at its tips (`subgrid_records`). Across walls a wavenumber is
    /// rounded to a whole number of half waves across the grid and the mode
    /// paired with its mirror images (the normal component then vanishes on
    /// both walls: the modes of a channel). The whole is scaled so that the
    /// horizontal components' variance, averaged over draws, is 1 (the
    /// modes, the grid's and the sub-grid's, carry it all); a single
    /// instant's field is a draw away from it.
    pub fn new(turbulence: &Turbulence, cells: UVec3, cell: Vec3, walls: [bool; 3]) -> Self {
        let h = cell.as_dvec3();
        let k_e = PEAK_TIMES_LENGTH / turbulence.length_scale as f64;
        let k_lo = LOWEST * k_e;
        let k_hi = (std::f64::consts::PI / h.max_element()).max(k_lo * 1.01);
        let k_finest = std::f64::consts::TAU / turbulence.finest_wavelength() as f64;
        let subgrid = k_finest > k_hi * 1.01;
        let k_top = if subgrid { k_finest } else { k_hi };
        let log_shells = |lo: f64, hi: f64, shells: usize| {
            let span = (hi / lo).ln();
            (0..shells).map(move |n| {
                let edge = |n: usize| lo * (span * n as f64 / shells as f64).exp();
                (edge(n), edge(n + 1))
            })
        };
        let span = (k_top / k_lo).ln();
        let fine = 16 * (SHELLS + SUBGRID_SHELLS);
        let spectrum = VonKarman {
            k_e,
            integral: (0..fine)
                .map(|n| {
                    let k = k_lo * (span * (n as f64 + 0.5) / fine as f64).exp();
                    VonKarman::shape(k, k_e) * span / fine as f64 * k
                })
                .sum::<f64>(),
        };
        let mut offsets = rand_pcg::Pcg32::seed_from_u64(draw_key(turbulence.seed, u64::MAX, -1));
        let subgrid_shells = if subgrid { SUBGRID_SHELLS } else { 0 };
        let shells = log_shells(k_lo, k_hi, SHELLS)
            .chain(log_shells(k_hi, k_top, subgrid_shells))
            .map(|(lo, hi)| Shell {
                k_lo: lo,
                k_hi: hi,
                life: LIFE / spectrum.rate((lo * hi).sqrt()).max(spectrum.rate(k_e)),
                offset: offsets.random::<f64>(),
            })
            .collect();
        let mut field = Self {
            seed: turbulence.seed,
            shells,
            spectrum,
            scale: 1.0,
            size: cells.as_dvec3() * h,
            mirrored: (0..3).filter(|&a| walls[a]).map(|a| 1u32 << a).sum(),
            cell,
            drift: DVec3::ZERO,
            clock: 0.0,
        };
        field.scale = (2.0 / field.mean_variance(walls).max(f64::MIN_POSITIVE)).sqrt();
        field
    }

    /// The field's horizontal variance averaged over draws, before scaling.
    fn mean_variance(&self, walls: [bool; 3]) -> f64 {
        // Each draw's horizontal variance over the grid: half its
        // amplitude squared along the axes not mirrored, and per mirrored
        // axis a half where the mode has waves across it (none for the
        // component across it where it has none: sin 0).
        let horizontal = |m: &Mode| -> f64 {
            [0, 2]
                .iter()
                .map(|&axis| {
                    let mut share = 0.5;
                    for a in (0..3).filter(|&a| walls[a]) {
                        share *= match (m.k[a] != 0.0, a == axis) {
                            (true, _) => 0.5,
                            (false, true) => 0.0,
                            (false, false) => 1.0,
                        };
                    }
                    m.amplitude[axis].powi(2) * share
                })
                .sum()
        };
        // At every instant each shell's two weights squared add to 1, so
        // the field's mean variance is the sum over shells of a draw's.
        (0..self.slots())
            .map(|slot| {
                (0..SCALE_DRAWS as i64)
                    .map(|g| horizontal(&self.draw(slot, g)))
                    .sum::<f64>()
                    / (2 * SCALE_DRAWS) as f64
            })
            .sum()
    }

    /// The modes' slots: the grid's `MODES`, then the sub-grid's.
    fn slots(&self) -> usize {
        2 * self.shells.len()
    }

    /// How many modes finer than the grid the tips sum: 0 or
    /// `SUBGRID_MODES`.
    pub fn subgrid_count(&self) -> usize {
        self.slots() - MODES
    }

    /// Mode `slot`'s draw of `generation`, the same for the same seed.
    fn draw(&self, slot: usize, generation: i64) -> Mode {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(draw_key(self.seed, slot as u64, generation));
        let shell = self.shells[slot / 2];
        let k = shell.k_lo * (shell.k_hi / shell.k_lo).powf(rng.random::<f64>());
        // E(k) dk over the shell, sampled log-uniform: dk = k ln(hi / lo).
        let weight = self.spectrum.energy(k) * k * (shell.k_hi / shell.k_lo).ln();
        let mut wavenumber = unit_on_sphere(&mut rng) * k;
        for a in (0..3).filter(|&a| self.is_mirrored(a)) {
            let half_wave = std::f64::consts::PI / self.size[a];
            wavenumber[a] = (wavenumber[a].abs() / half_wave).round() * half_wave;
        }
        let (e1, e2) = wavenumber
            .try_normalize()
            .unwrap_or(DVec3::X)
            .any_orthonormal_pair();
        let angle = rng.random::<f64>() * std::f64::consts::TAU;
        let a = (e1 * angle.cos() + e2 * angle.sin()) * weight.sqrt();
        let phase = rng.random::<f64>() * std::f64::consts::TAU;
        // The grid's modes as its faces hold them; the sub-grid's as they
        // are, summed at a point (`velocity_at`).
        let amplitude = if slot < MODES {
            face_amplitude(wavenumber, a, self.cell.as_dvec3())
        } else {
            a
        };
        Mode {
            k: wavenumber,
            amplitude,
            phase,
            omega: self.spectrum.rate(k),
        }
    }

    /// Mode `slot`'s generation and its weight now: sin(pi s) of its age s
    /// over its life, the shell's second mode half a life after its first.
    fn age(&self, slot: usize) -> (i64, f64) {
        let shell = self.shells[slot / 2];
        let lives = self.clock / shell.life + shell.offset + 0.5 * (slot % 2) as f64;
        let generation = lives.floor();
        (
            generation as i64,
            (std::f64::consts::PI * (lives - generation)).sin(),
        )
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
    /// glsl/wind/turbulence.comp sums it (`component_at`).
    pub fn at(&self, records: &[TurbulenceMode], axis: usize, q: UVec3) -> f32 {
        component_at(records, axis, q.as_vec3() * 0.5 * self.cell)
    }

    /// Component `axis` of the field `records` describe at every face of
    /// a lattice of `dims` faces, in storage order (`component_on_faces`).
    pub fn on_faces(&self, records: &[TurbulenceMode], axis: usize, dims: UVec3) -> Vec<f64> {
        component_on_faces(records, axis, dims, self.cell)
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

    /// The grid's modes as the GPU reads them now, for a standard
    /// deviation of `sigma` (m/s): each slot's draw of its current
    /// generation, weighed by where it is in its life, at the phase theta_n
    /// = phi_n + omega_n int(sigma dt) - k_n . int(U dt) (along the axes
    /// not mirrored), in double precision, reduced to [0, 2 pi).
    pub fn records(&self, sigma: f32) -> Vec<TurbulenceMode> {
        (0..MODES).map(|slot| self.record(slot, sigma)).collect()
    }

    /// The modes finer than the grid, the same way, which the grass sums
    /// at its tips (`velocity_at`): none where the grid holds the finest
    /// wavelength the scene asks for.
    pub fn subgrid_records(&self, sigma: f32) -> Vec<TurbulenceMode> {
        (MODES..self.slots())
            .map(|slot| self.record(slot, sigma))
            .collect()
    }

    fn record(&self, slot: usize, sigma: f32) -> TurbulenceMode {
        let (generation, weight) = self.age(slot);
        let m = self.draw(slot, generation);
        let carried: f64 = (0..3)
            .filter(|&a| self.mirrored & (1 << a) == 0)
            .map(|a| m.k[a] * self.drift[a])
            .sum();
        let phase = (m.phase + m.omega * self.clock - carried).rem_euclid(std::f64::consts::TAU);
        TurbulenceMode {
            wavenumber: m.k.as_vec3().to_array(),
            phase: phase as f32,
            amplitude: (m.amplitude * self.scale * weight * sigma as f64)
                .as_vec3()
                .to_array(),
            mirrored: self.mirrored,
        }
    }
}

/// Mode `m`'s wavenumber, and its phase at `x` along the axes it is not
/// mirrored across (theta' of `component_at`).
fn free_phase(m: &TurbulenceMode, x: Vec3) -> ([f32; 3], f32) {
    let k = m.wavenumber;
    let mut theta = m.phase;
    for a in 0..3 {
        if m.mirrored & (1 << a) == 0 {
            theta += k[a] * x[a];
        }
    }
    (k, theta)
}

/// Component `axis` of the field `records` describe at `x` (m from the
/// grid's minimum corner), as glsl/common/turbulence.glsl sums it. A mode
/// a cos(k . x + theta) paired with its mirror images across the walls of
/// the axes m in `mirrored` is, for each component, cos(theta') (or
/// -sin(theta') for the component across a mirrored axis) times, per
/// mirrored axis m, sin(k_m x_m) for the component across it and cos(k_m
/// x_m) for the others, theta' the phase along the axes not mirrored: the
/// normal component is zero on both walls.
pub fn component_at(records: &[TurbulenceMode], axis: usize, x: Vec3) -> f32 {
    let mut u = 0.0;
    for m in records {
        let (k, theta) = free_phase(m, x);
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

/// Component `axis` of the field `records` describe at every face of a
/// lattice of `dims` faces (x fastest, then y, then z) whose face (i, j,
/// k) is at half-cell point `face_point(axis, [i, j, k])`, cell `cell`
/// (m): `component_at` at each, summed the same way but separated. A
/// mode's cos(k . x + theta) along the free axes is the real part of
/// e^(i theta) times one phasor e^(i k_a x_a) per axis, and its mirrored
/// factors depend on one coordinate each, so each mode needs a sine and a
/// cosine per lattice line instead of two to four per face (the CPU
/// step's turbulence was most of its time). In double precision: it
/// differs from `component_at`'s single-precision phase by that
/// rounding, about 1e-5 of a mode's amplitude.
pub fn component_on_faces(
    records: &[TurbulenceMode],
    axis: usize,
    dims: UVec3,
    cell: Vec3,
) -> Vec<f64> {
    let n = [dims.x as usize, dims.y as usize, dims.z as usize];
    let mut out = vec![0.0f64; n[0] * n[1] * n[2]];
    // Per axis a, the coordinate of lattice index i: along the component's
    // own axis the faces are at whole cells, across it at half cells.
    let coord = |a: usize, i: usize| {
        let q = 2 * i + usize::from(a != axis);
        (q as f32 * 0.5 * cell[a]) as f64
    };
    for m in records {
        let (k, phase) = (m.wavenumber.map(f64::from), m.phase);
        // Per axis and lattice index: the free phasor (cos, sin) of k_a
        // x_a, or for a mirrored axis the real factor it contributes.
        let lines: [Vec<(f64, f64)>; 3] = std::array::from_fn(|a| {
            (0..n[a])
                .map(|i| {
                    let (sin, cos) = (k[a] * coord(a, i)).sin_cos();
                    if m.mirrored & (1 << a) == 0 {
                        (cos, sin)
                    } else if a == axis {
                        (sin, 0.0)
                    } else {
                        (cos, 0.0)
                    }
                })
                .collect()
        });
        let mul = |p: (f64, f64), a: usize, i: usize| {
            let (c, s) = lines[a][i];
            if m.mirrored & (1 << a) == 0 {
                (p.0 * c - p.1 * s, p.0 * s + p.1 * c)
            } else {
                (p.0 * c, p.1 * c)
            }
        };
        let across = m.mirrored & (1 << axis) != 0;
        let amplitude = m.amplitude[axis] as f64;
        let start = (phase as f64).sin_cos();
        for kk in 0..n[2] {
            let pz = mul((start.1, start.0), 2, kk);
            for j in 0..n[1] {
                let py = mul(pz, 1, j);
                let row = &mut out[(kk * n[1] + j) * n[0]..][..n[0]];
                for (i, u) in row.iter_mut().enumerate() {
                    let p = mul(py, 0, i);
                    // cos(theta') or, across a mirrored axis, -sin(theta').
                    *u += amplitude * if across { -p.1 } else { p.0 };
                }
            }
        }
    }
    out
}

/// The velocity the modes `records` describe at `x` (m from the grid's
/// minimum corner): what the sub-grid modes add to the wind a blade's tip
/// feels (`WindField::felt`; glsl/grass/step.glsl).
pub fn velocity_at(records: &[TurbulenceMode], x: Vec3) -> Vec3 {
    Vec3::new(
        component_at(records, 0, x),
        component_at(records, 1, x),
        component_at(records, 2, x),
    )
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
fn face_amplitude(k: DVec3, a: DVec3, h: DVec3) -> DVec3 {
    let modified = DVec3::new(
        2.0 * (0.5 * k.x * h.x).sin() / h.x,
        2.0 * (0.5 * k.y * h.y).sin() / h.y,
        2.0 * (0.5 * k.z * h.z).sin() / h.z,
    );
    -modified.cross(k.cross(a)) / k.length_squared()
}
