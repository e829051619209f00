//! CPU reference of the wind solver (paper section 3.2; docs/method.md section 3):
//! inviscid, incompressible Navier-Stokes on a grid, one step =
//! add source forces -> advection (MacCormack's corrector on the paper's
//! semi-Lagrangian step by default, or that step alone) -> divergence ->
//! pressure (multigrid V-cycles by default, src/model/multigrid.rs, or the
//! paper's Jacobi iterations) -> subtract the pressure gradient; with
//! turbulence (src/model/turbulence.rs) its field is added on top (before
//! the projection among solid cells).
//!
//! Its children: `faces.rs`, what each cell and face is (solid, ground,
//! free, wall, inflow, buried) and the classification a grid alone gets;
//! `window.rs`, the window that follows a cover's camera. They use this
//! file's grid, settings and field.
//!
//! A staggered (MAC) grid: the x component lives on the cells' x faces, y on
//! y faces, z on z faces, pressure at cell centres. Divergence and gradient
//! are then compact differences and the projection converges to a
//! divergence-free field as the Jacobi count grows.
//!
//! Boundaries (ours, docs/method.md): the grid's floor and solid cells (the
//! obstacles', and those under the ground's height field) are no-through
//! (their faces hold zero); the top is free-slip (no flow through it,
//! tangential flow free); the four sides are open: the pressure outside
//! is zero, so wind leaves the domain. An inflow's entry sides (one or two,
//! from its heading) hold their faces at its velocity across them; a side
//! along it is free-slip (a wind tunnel: what enters leaves through the
//! far sides).
//!
//! The GPU compute shaders in glsl/wind/ follow this file kernel by kernel.

use glam::{UVec3, Vec3};

mod faces;
mod window;

use super::contact::{Collider, ColliderState};
use super::multigrid::{Multigrid, Work};
pub use super::path::{along_path, MAX_PATH_POINTS};
use super::terrain::Terrain;
pub use super::turbulence::Turbulence;
use super::turbulence::TurbulenceField;
use crate::error::{Error, Result};
use crate::interface::TurbulenceMode;
use faces::multigrid_of;
pub use faces::{voxelised, Cells, Classification, FaceKind};

/// The grid: `cells` = (nx, ny, nz), x and z horizontal, y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindGrid {
    pub cells: UVec3,
    /// World position of the grid's minimum corner.
    pub origin: Vec3,
    /// Size of one cell along x, y, z (metres).
    pub cell: Vec3,
}

/// The most cells one grid may have (the paper's is 72,000).
pub const MAX_CELLS: u64 = 64 * 1024 * 1024;

impl WindGrid {
    pub fn new(cells: UVec3, origin: Vec3, size: Vec3) -> Result<Self> {
        let n = cells.as_u64vec3();
        if cells.min_element() == 0 || n.x * n.y * n.z > MAX_CELLS {
            return Err(Error::InvalidInput(format!(
                "wind grid {}x{}x{} is not allowed, use at least 1 cell per axis and at most {MAX_CELLS} cells",
                cells.x, cells.y, cells.z
            )));
        }
        if !(size.is_finite() && size.min_element() > 0.0 && origin.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "wind domain size {size} at {origin} is not allowed, use finite positive sizes"
            )));
        }
        Ok(Self {
            cells,
            origin,
            cell: size / cells.as_vec3(),
        })
    }

    /// The divergence f32 arithmetic leaves in any field whose faces reach
    /// `max_speed` (m/s) on this grid: each face value rounded by up to
    /// half an ulp of the fastest, six of them over the smallest cell side,
    /// with a factor for the solve's own rounding. Below it a projection
    /// has nothing left to remove (1/s).
    pub fn divergence_floor(&self, max_speed: f32) -> f32 {
        4.0 * f32::EPSILON * max_speed.abs() / self.cell.min_element()
    }

    pub fn cell_count(&self) -> usize {
        (self.cells.x * self.cells.y * self.cells.z) as usize
    }

    /// Faces of all three velocity components: one velocity copy's length.
    pub fn face_count(&self) -> u64 {
        (0..3)
            .map(|a| self.face_dims(a).as_u64vec3().element_product())
            .sum()
    }

    /// Number of samples of velocity component `axis` (one more along its own axis).
    pub fn face_dims(&self, axis: usize) -> UVec3 {
        let mut d = self.cells;
        d[axis] += 1;
        d
    }

    pub fn cell_index(&self, i: u32, j: u32, k: u32) -> usize {
        (i + self.cells.x * (j + self.cells.y * k)) as usize
    }

    pub fn face_index(&self, axis: usize, i: u32, j: u32, k: u32) -> usize {
        let d = self.face_dims(axis);
        (i + d.x * (j + d.y * k)) as usize
    }

    /// World position of face sample (i, j, k) of component `axis`.
    pub fn face_position(&self, axis: usize, i: u32, j: u32, k: u32) -> Vec3 {
        let mut offset = Vec3::splat(0.5);
        offset[axis] = 0.0;
        self.origin + (UVec3::new(i, j, k).as_vec3() + offset) * self.cell
    }

    pub fn cell_center(&self, i: u32, j: u32, k: u32) -> Vec3 {
        self.origin + (UVec3::new(i, j, k).as_vec3() + 0.5) * self.cell
    }

    pub fn size(&self) -> Vec3 {
        self.cell * self.cells.as_vec3()
    }

    /// Every sample of velocity component `axis` in storage order:
    /// (index, [i, j, k]).
    pub fn each_face(self, axis: usize) -> impl Iterator<Item = (usize, [u32; 3])> {
        lattice(self.face_dims(axis))
    }

    /// Every cell in storage order: (index, [i, j, k]).
    pub fn each_cell(self) -> impl Iterator<Item = (usize, [u32; 3])> {
        lattice(self.cells)
    }
}

/// The points of a `d.x` x `d.y` x `d.z` lattice, x fastest, numbered in that order.
fn lattice(d: UVec3) -> impl Iterator<Item = (usize, [u32; 3])> {
    (0..d.z)
        .flat_map(move |k| (0..d.y).flat_map(move |j| (0..d.x).map(move |i| [i, j, k])))
        .enumerate()
}

/// Gusts: the signal
/// g(t) = 0.5 sin(2 pi f t + p0) + 0.3 sin(2 pi 2.17 f t + p1) + 0.2 sin(2 pi 4.73 f t + p2),
/// the phases p drawn from the seed. A source's strength is
/// s0 * max(0, 1 + a g(t)); an inflow's gusts are spatial and travel
/// (`Inflow::velocity_at`). a = 0: no gusts. In a scene file every field
/// is optional on its own (default 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Gust {
    pub amplitude: f32,
    /// Base frequency, Hz.
    pub frequency: f32,
    pub seed: u32,
}

impl Gust {
    pub const HARMONICS: [(f32, f32); 3] = [(1.0, 0.5), (2.17, 0.3), (4.73, 0.2)];

    /// The three phases, from the seed (a small integer hash, same on GPU upload).
    pub fn phases(&self) -> [f32; 3] {
        std::array::from_fn(|n| {
            let mut x = self
                .seed
                .wrapping_mul(0x9E37_79B9)
                .wrapping_add((n as u32).wrapping_mul(0x85EB_CA6B));
            x ^= x >> 16;
            x = x.wrapping_mul(0x7FEB_352D);
            x ^= x >> 15;
            (x as f32 / u32::MAX as f32) * std::f32::consts::TAU
        })
    }

    /// g at time t, each harmonic delayed by its own `delay` (s).
    fn signal(&self, t: f32, delay: [f32; 3]) -> f32 {
        let p = self.phases();
        Self::HARMONICS
            .iter()
            .zip(p)
            .zip(delay)
            .map(|((&(mult, weight), phase), delay)| {
                weight * (std::f32::consts::TAU * self.frequency * mult * (t - delay) + phase).sin()
            })
            .sum()
    }

    /// A source's strength factor at time t: max(0, 1 + a g(t)).
    pub fn factor(&self, t: f32) -> f32 {
        if self.amplitude == 0.0 {
            return 1.0;
        }
        (1.0 + self.amplitude * self.signal(t, [0.0; 3])).max(0.0)
    }
}

/// How far each harmonic's gust fronts lean across the inflow side: a
/// front reaches z later by `INFLOW_GUST_LEAN * z / |speed|` (harmonics 1
/// and 3) or earlier (harmonic 2), so fronts arrive oblique (about 27
/// degrees) and crossing, not as one wall along the whole side.
pub const INFLOW_GUST_LEAN: f32 = 0.5;
const INFLOW_GUST_LEAN_SIGN: [f32; 3] = [1.0, -1.0, 1.0];

impl Inflow {
    /// The inflow's velocity component `axis` (0: x, 2: z) at a point `x`
    /// of an entry side of `grid`, at time t (docs/physics.md, travelling
    /// gusts):
    ///
    /// u = U d (1 + a g(t - delay) cos(pi y / height)),
    ///
    /// d the heading's unit vector, y the height above the grid's floor
    /// and the delay the time a front takes to arrive: (x - x0) . d / |U|
    /// from the most upwind corner x0, plus the lean of the fronts across
    /// the wind, lean (x . d_perp) / |U| with d_perp = (-d_z, d_x)
    /// (heading 0: lean z / |U|).
    ///
    /// A gust is faster air near the ground and slower air aloft: the
    /// cosine has zero mean over the height, so the flux through the side
    /// stays U times its area at every instant and the projection cannot
    /// pass the gust through the whole field at once; advection carries it
    /// downwind at the wind's speed (the lowest vertical mode of the layer
    /// of air between the ground and the free-slip top travels unchanged).
    pub fn velocity_at(&self, axis: usize, grid: &WindGrid, x: Vec3, t: f32) -> f32 {
        let [c, s] = self.heading_vector();
        let component = if axis == 0 { c } else { s };
        if self.gust.amplitude == 0.0 {
            return self.speed * component;
        }
        let speed = self.speed.abs().max(1e-3);
        let lean = INFLOW_GUST_LEAN * (-s * x.x + c * x.z) / speed;
        // The most upwind corner of the grid, along the velocity.
        let size = grid.size();
        let corner = |d: f32, lo: f32, extent: f32| {
            if d * self.speed < 0.0 {
                lo + extent
            } else {
                lo
            }
        };
        let x0 = corner(c, grid.origin.x, size.x);
        let z0 = corner(s, grid.origin.z, size.z);
        let sign = if self.speed >= 0.0 { 1.0 } else { -1.0 };
        let arrival = sign * ((x.x - x0) * c + (x.z - z0) * s) / speed;
        let delay = INFLOW_GUST_LEAN_SIGN.map(|l| l * lean + arrival);
        let height = size.y;
        let profile = (std::f32::consts::PI * (x.y - grid.origin.y) / height).cos();
        self.speed * (1.0 + self.gust.amplitude * self.gust.signal(t, delay) * profile) * component
    }
}

impl Inflow {
    /// The inflow's component `axis` that air traced back to `back`
    /// carries in from outside, at time t: for a horizontal component
    /// whose trace left the grid through an entry side across the other
    /// horizontal axis (the inflow's tangential part along that side,
    /// which no face of the side holds), the inflow's velocity at the
    /// side; None otherwise, for a component the inflow has none of
    /// (heading 0: z), so a wind from the left is unchanged bit for bit,
    /// and for an inflow stilled to 0 m/s.
    pub fn entering(&self, axis: usize, grid: &WindGrid, back: Vec3, t: f32) -> Option<f32> {
        let [c, s] = self.heading_vector();
        if self.speed == 0.0 || axis == 1 || (if axis == 0 { c } else { s }) == 0.0 {
            return None;
        }
        let across = 2 - axis;
        let (lo, hi) = (
            grid.origin[across],
            grid.origin[across] + grid.size()[across],
        );
        let outside = match (self.side(across, 0), self.side(across, 1)) {
            (Side::Entry, _) => back[across] < lo,
            (_, Side::Entry) => back[across] > hi,
            _ => false,
        };
        outside.then(|| {
            let at = back.clamp(grid.origin, grid.origin + grid.size());
            self.velocity_at(axis, grid, at, t)
        })
    }
}

/// A wind source (docs/method.md section 3): a ball of force.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindSource {
    pub position: Vec3,
    /// Direction of the force at t = 0 (normalised on use).
    pub direction: Vec3,
    /// Force per unit mass at the centre (m/s^2).
    pub strength: f32,
    /// Radius of influence (m); the force falls off smoothly to zero there.
    pub radius: f32,
    /// The direction turns about the vertical at this rate (rad/s): paper Fig. 11.
    #[serde(default)]
    pub rotation_speed: f32,
    /// Waypoints of a closed path the source moves along (empty: it stays put).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<Vec3>,
    /// Speed along the path (m/s).
    #[serde(default)]
    pub path_speed: f32,
    #[serde(default)]
    pub gust: Gust,
    /// Sources can be switched off at this time (s); None: never.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub off_after: Option<f32>,
}

impl WindSource {
    pub fn fixed(position: Vec3, direction: Vec3, strength: f32, radius: f32) -> Self {
        Self {
            position,
            direction,
            strength,
            radius,
            rotation_speed: 0.0,
            path: Vec::new(),
            path_speed: 0.0,
            gust: Gust::default(),
            off_after: None,
        }
    }

    /// Position, unit direction and strength at time t.
    pub fn at(&self, t: f32) -> (Vec3, Vec3, f32) {
        let d = self.direction.try_normalize().unwrap_or(Vec3::X);
        let dir = turned_about_y(d, self.rotation_speed * t);
        let strength = match self.off_after {
            Some(off) if t >= off => 0.0,
            _ => self.strength * self.gust.factor(t),
        };
        (self.position_at(t), dir, strength)
    }

    fn position_at(&self, t: f32) -> Vec3 {
        along_path(&self.path, self.path_speed, true, t, self.position).0
    }

    /// Refuses what cannot be simulated; warns where the source lies
    /// outside `grid`.
    pub fn validate(&self, grid: &WindGrid) -> Result<Vec<String>> {
        let finite = self.position.is_finite()
            && self.direction.is_finite()
            && self.strength.is_finite()
            && self.radius.is_finite()
            && self.rotation_speed.is_finite()
            && self.path_speed.is_finite()
            && self.path.iter().all(|p| p.is_finite())
            && self.gust.amplitude.is_finite()
            && self.gust.frequency.is_finite();
        if !finite {
            return Err(Error::InvalidInput(
                "wind source: every value must be a finite number (found NaN or infinity)".into(),
            ));
        }
        if self.radius <= 0.0 {
            return Err(Error::InvalidInput(format!(
                "wind source radius {} is not allowed, use > 0",
                self.radius
            )));
        }
        let mut warnings = Vec::new();
        let lo = grid.origin;
        let hi = grid.origin + grid.size();
        let p = self.position;
        if p.cmplt(lo).any() || p.cmpgt(hi).any() {
            warnings.push(format!(
                "wind source at {} lies outside the wind domain {lo}..{hi}; only its reach inside counts",
                self.position
            ));
        }
        Ok(warnings)
    }
}

/// `v` turned by `angle` radians about +y (anticlockwise seen from above):
/// a rotating source's direction (paper Fig. 11), the viewer's heading.
pub fn turned_about_y(v: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    Vec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
}

/// Smooth fall-off of a source's force with distance: (1 - (d/r)^2)^2 inside r.
pub fn falloff(distance: f32, radius: f32) -> f32 {
    let q = 1.0 - (distance / radius) * (distance / radius);
    if q > 0.0 {
        q * q
    } else {
        0.0
    }
}

/// Wind entering through one side of the domain (paper Fig. 10: from the left).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Inflow {
    /// Speed of the incoming air (m/s); negative blows against `heading`.
    pub speed: f32,
    /// Where it blows towards, degrees: 0 along +x (paper Fig. 10: from
    /// the left), 90 along +z. The sides it enters by and leaves by
    /// follow from it (`Inflow::side`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub heading: f32,
    #[serde(default)]
    pub gust: Gust,
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

/// What a side of the domain is to an inflow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The wind enters: its faces hold the inflow's velocity across them.
    Entry,
    /// The wind leaves: open, zero pressure outside.
    Exit,
    /// Along the wind: free-slip, as a wind tunnel's walls.
    Along,
}

impl Inflow {
    /// The unit vector (x, z) the heading points along; exactly (1, 0)
    /// at heading 0, so that today's wind from the left is unchanged bit
    /// for bit (glsl/wind/wind_kernel.glsl does the same).
    pub fn heading_vector(&self) -> [f32; 2] {
        if self.heading == 0.0 {
            return [1.0, 0.0];
        }
        let (s, c) = self.heading.to_radians().sin_cos();
        // A component under 1e-6 is the rounding of a heading along an
        // axis (cos 90 degrees is -4e-8 in f32): zero.
        let snap = |v: f32| if v.abs() < 1e-6 { 0.0 } else { v };
        [snap(c), snap(s)]
    }

    /// Its mean velocity (m/s): speed along the heading, none upwards.
    pub fn mean_velocity(&self) -> Vec3 {
        let [c, s] = self.heading_vector();
        Vec3::new(self.speed * c, 0.0, self.speed * s)
    }

    /// Whether the inflow blows across both horizontal axes.
    pub fn is_oblique(&self) -> bool {
        let [c, s] = self.heading_vector();
        c != 0.0 && s != 0.0
    }

    /// Side `end` (0: least, 1: greatest) across horizontal axis `axis`
    /// (0: x, 2: z). Only the heading and the speed's sign decide, so a
    /// speed set to zero keeps the sides; a side the heading has no
    /// component across lies along the wind.
    pub fn side(&self, axis: usize, end: u32) -> Side {
        let [c, s] = self.heading_vector();
        let sign = if self.speed >= 0.0 { 1.0 } else { -1.0 };
        let component = sign * if axis == 0 { c } else { s };
        let inward = if end == 0 { component } else { -component };
        if component == 0.0 {
            Side::Along
        } else if inward > 0.0 {
            Side::Entry
        } else {
            Side::Exit
        }
    }
}

/// An obstacle in world space (paper Fig. 13): an axis-aligned box, a
/// sphere, or an upright cylinder (a tree trunk, a post) standing on `base`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase", tag = "kind", deny_unknown_fields)]
pub enum Obstacle {
    Box {
        min: Vec3,
        max: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Cylinder {
        base: Vec3,
        radius: f32,
        height: f32,
    },
}

impl Obstacle {
    pub fn contains(&self, p: Vec3) -> bool {
        match *self {
            Obstacle::Box { min, max } => p.cmpge(min).all() && p.cmple(max).all(),
            Obstacle::Sphere { center, radius } => p.distance_squared(center) <= radius * radius,
            Obstacle::Cylinder {
                base,
                radius,
                height,
            } => {
                let d = p - base;
                (0.0..=height).contains(&d.y) && d.x * d.x + d.z * d.z <= radius * radius
            }
        }
    }
}

/// How the projection solves for the pressure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PressureSolver {
    /// V-cycles of geometric multigrid (src/model/multigrid.rs), the
    /// default: it converges (6 cycles leave under 1% of the divergence on
    /// the shipped scenes; docs/physics.md).
    #[default]
    Multigrid,
    /// The paper's Jacobi iterations, warm-started: 30 of them leave most
    /// of the divergence on the paper's grid.
    Jacobi,
}

impl PressureSolver {
    pub fn name(self) -> &'static str {
        match self {
            PressureSolver::Multigrid => "multigrid",
            PressureSolver::Jacobi => "jacobi",
        }
    }
}

/// Lattice coordinates within this of a whole number count as on it
/// when MacCormack's clamp picks its eight samples (`sample_range`, and
/// glsl/common/wind_sample.glsl's).
pub use crate::interface::WIND_RANGE_SNAP as RANGE_SNAP;

/// How the advection (kernel 2) carries the velocity.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Advection {
    /// MacCormack's predictor and corrector on the semi-Lagrangian step
    /// (Selle, Fedkiw, Kim, Liu and Rossignac 2008), clamped to the range
    /// of the values the predictor interpolated: second order, bounded;
    /// a gust keeps its strength down a field (docs/physics.md); the
    /// default.
    #[default]
    Maccormack,
    /// The paper's first-order semi-Lagrangian step (Stam 1999), which
    /// wears a gust away within tens of metres; the paper's figure scenes
    /// ask for it (docs/physics.md: behind fig13-obstacles' wall its
    /// numerical viscosity makes the calm lee the paper shows).
    SemiLagrangian,
}

impl Advection {
    pub fn name(self) -> &'static str {
        match self {
            Advection::Maccormack => "maccormack",
            Advection::SemiLagrangian => "semi-lagrangian",
        }
    }
}

/// Whether the grass slows the air (src/model/canopy.rs).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// The paper's: the wind moves the grass and the grass never touches
    /// the wind.
    #[default]
    OneWay,
    /// Ours (the paper's first item of future work): the canopy drag
    /// -C_d a |u| u slows the air where the blades stand.
    TwoWay,
}

impl Coupling {
    pub fn name(self) -> &'static str {
        match self {
            Coupling::OneWay => "one-way",
            Coupling::TwoWay => "two-way",
        }
    }
}

/// The canopy drag coefficient C_d by default: a plate across a flow has
/// about 1.2 alone; blades behind blades shelter each other, and field
/// canopies measured on frontal area give 0.1-0.5 (docs/physics.md).
pub const DEFAULT_CANOPY_DRAG: f32 = 0.3;

/// Everything that drives the wind.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WindSettings {
    pub sources: Vec<WindSource>,
    pub inflow: Option<Inflow>,
    pub obstacles: Vec<Obstacle>,
    /// The colliders (`[[collider]]`), which push the air as they move:
    /// moving obstacles (`WindField::add_forces`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub colliders: Vec<Collider>,
    pub solver: PressureSolver,
    /// Jacobi iterations of the pressure solve when `solver` is Jacobi
    /// (default 30; docs/method.md section 3).
    pub jacobi_iterations: u32,
    /// V-cycles per step when `solver` is multigrid (default 6).
    pub v_cycles: u32,
    /// Whether the grass slows the air.
    pub coupling: Coupling,
    /// C_d of the canopy drag when `coupling` is two-way.
    pub canopy_drag: f32,
    /// How the advection carries the velocity.
    pub advection: Advection,
    /// The fluctuating wind added to the solver's (none: the paper's).
    pub turbulence: Option<Turbulence>,
    /// The ground: cells whose centre lies under it are solid.
    #[serde(skip)]
    pub terrain: Terrain,
    /// The grid is a window that follows the camera (`wind.window` with
    /// `[grass.cover]`; src/model/wind/window.rs).
    #[serde(skip)]
    pub moving_window: bool,
}

impl WindSettings {
    /// C_d as the advection takes it: zero when the coupling is one-way.
    pub fn effective_canopy_drag(&self) -> f32 {
        match self.coupling {
            Coupling::OneWay => 0.0,
            Coupling::TwoWay => self.canopy_drag,
        }
    }

    /// The turbulence's sigma_u = intensity U (m/s), U its `speed` or else
    /// the inflow's |speed|; 0 without turbulence.
    pub fn turbulence_sigma(&self) -> f32 {
        self.turbulence.map_or(0.0, |t| {
            let reference = t.speed.or(self.inflow.map(|i| i.speed.abs()));
            t.intensity * reference.unwrap_or(0.0)
        })
    }

    /// Which axes' two sides hold no flow through them for the
    /// turbulence: the ground and the top, and the sides along an inflow
    /// (its modes are mirrored across them; src/model/turbulence.rs),
    /// except on a window that follows the camera: mirrored across its
    /// sides the field would move with them.
    pub fn turbulence_walls(&self) -> [bool; 3] {
        let along = |axis: usize| {
            !self.moving_window && self.inflow.is_some_and(|i| i.side(axis, 0) == Side::Along)
        };
        [along(0), true, along(2)]
    }

    /// The turbulence's patches move with the inflow's mean velocity
    /// (m/s); without an inflow they change in place.
    pub fn turbulence_convection(&self) -> Vec3 {
        self.inflow.map_or(Vec3::ZERO, |i| i.mean_velocity())
    }
}

impl Default for WindSettings {
    /// Still air, solved by the default solver.
    fn default() -> Self {
        Self {
            sources: Vec::new(),
            inflow: None,
            obstacles: Vec::new(),
            colliders: Vec::new(),
            solver: PressureSolver::default(),
            jacobi_iterations: DEFAULT_JACOBI_ITERATIONS,
            v_cycles: DEFAULT_V_CYCLES,
            coupling: Coupling::default(),
            canopy_drag: DEFAULT_CANOPY_DRAG,
            advection: Advection::default(),
            turbulence: None,
            terrain: Terrain::default(),
            moving_window: false,
        }
    }
}

pub const DEFAULT_JACOBI_ITERATIONS: u32 = 30;
pub use super::multigrid::DEFAULT_V_CYCLES;

impl WindSettings {
    /// Refuses a source that cannot be simulated; returns a line for each
    /// one that can but will do little (e.g. outside the grid).
    pub fn check(&self, grid: &WindGrid) -> Result<Vec<String>> {
        let mut warnings = Vec::new();
        for source in &self.sources {
            warnings.extend(source.validate(grid)?);
        }
        for (i, obstacle) in self.obstacles.iter().enumerate() {
            let solid = grid
                .each_cell()
                .any(|(_, [x, y, z])| obstacle.contains(grid.cell_center(x, y, z)));
            if !solid {
                warnings.push(format!(
                    "wind obstacle {i} covers no cell of the wind domain {}..{}; it blocks no air",
                    grid.origin,
                    grid.origin + grid.size()
                ));
            }
        }
        Ok(warnings)
    }
}

/// The solver state on the CPU.
#[derive(Clone, Debug)]
pub struct WindField {
    pub grid: WindGrid,
    /// Velocity components on their faces: [x, y, z].
    pub vel: [Vec<f32>; 3],
    pub pressure: Vec<f32>,
    pub divergence: Vec<f32>,
    pub solid: Vec<bool>,
    /// The solid cells that lie under the ground (not an obstacle's).
    pub ground: Vec<bool>,
    /// What each velocity sample is: free, wall, inflow or buried (fixed
    /// per scene, or per inflow heading).
    pub faces: [Vec<FaceKind>; 3],
    /// The grass's frontal area in each cell, in counts of `canopy_unit`
    /// m^2, laid by the last grass step (src/model/canopy.rs); all zero
    /// unless the coupling is two-way.
    pub canopy: Vec<u32>,
    /// Square metres per count of `canopy` (0 until grass is coupled).
    pub canopy_unit: f32,
    /// The multigrid hierarchy of this grid's faces, and its coarse levels' storage.
    pub multigrid: Multigrid,
    /// The turbulence's modes (None: no turbulence).
    pub turbulence: Option<TurbulenceField>,
    /// What the last step added of the turbulence on each face, taken off
    /// again before the next (zero without turbulence).
    pub turbulence_added: [Vec<f32>; 3],
    /// The turbulence's modes finer than the grid as the last step left
    /// them (`TurbulenceField::subgrid_records`), which `felt` adds at a
    /// blade's tip; empty without.
    pub subgrid_turbulence: Vec<TurbulenceMode>,
    multigrid_work: Work,
    pub time: f32,
}

impl WindField {
    /// Voxelises the obstacles and the ground and classifies every face,
    /// once: a cell is solid where its centre lies inside an obstacle or
    /// under the ground (a staircase whose treads lie at the ground's
    /// height rounded to the nearest face; docs/method.md).
    pub fn new(grid: WindGrid, settings: &WindSettings) -> Self {
        let (ground, solid) = voxelised(&grid, settings);
        let mut field = Self {
            vel: [0, 1, 2].map(|a| {
                let d = grid.face_dims(a);
                vec![0.0; (d.x * d.y * d.z) as usize]
            }),
            pressure: vec![0.0; grid.cell_count()],
            divergence: vec![0.0; grid.cell_count()],
            canopy: vec![0; grid.cell_count()],
            canopy_unit: 0.0,
            solid,
            ground,
            faces: [Vec::new(), Vec::new(), Vec::new()],
            multigrid: Multigrid::default(),
            multigrid_work: Work::default(),
            turbulence: settings.turbulence.map(|t| {
                TurbulenceField::new(&t, grid.cells, grid.cell, settings.turbulence_walls())
            }),
            turbulence_added: [0, 1, 2].map(|a| {
                let d = grid.face_dims(a);
                vec![0.0; (d.x * d.y * d.z) as usize]
            }),
            subgrid_turbulence: Vec::new(),
            grid,
            time: 0.0,
        };
        field.classify_faces(settings.inflow.as_ref());
        // The modes finer than the grid as they start (the GPU's wind pass
        // hands the same to a trace's first sample); the first step's
        // forces take them on from there.
        if let Some(turbulence) = &field.turbulence {
            field.subgrid_turbulence = turbulence.subgrid_records(settings.turbulence_sigma());
        }
        if let Some(inflow) = settings
            .inflow
            .filter(|i| i.is_oblique() || !settings.terrain.is_flat())
        {
            field.start_with(&inflow);
        }
        field
    }

    /// The air at the inflow's mean velocity on every free face (and the
    /// ghost values under the ground), the first projection then turning
    /// it around the terrain and obstacles. Started from rest instead, an
    /// oblique inflow leaves the first projection's potential flow, which
    /// leaves the open exit sides at right angles (zero pressure there),
    /// for the inflow to flush out over several crossings of the grid;
    /// over terrain the ground's staircase would start the air in
    /// eddies. A wind along an axis over flat ground starts from rest, as
    /// it always has (its first projection gives the uniform flow).
    fn start_with(&mut self, inflow: &Inflow) {
        let mean = inflow.mean_velocity();
        for axis in [0, 2] {
            for (v, kind) in self.vel[axis].iter_mut().zip(&self.faces[axis]) {
                if matches!(kind, FaceKind::Free | FaceKind::Buried) {
                    *v = mean[axis];
                }
            }
        }
    }

    /// Classifies every face for `inflow` (its entry, exit and along
    /// sides) and builds the multigrid hierarchy of the free faces; a
    /// wind whose inflow turns calls it again (the viewer's arrows).
    /// Returns whether any face changed its kind.
    pub fn classify_faces(&mut self, inflow: Option<&Inflow>) -> bool {
        let cells = Cells {
            grid: &self.grid,
            solid: &self.solid,
            ground: &self.ground,
        };
        let faces = cells.face_kinds(inflow);
        if faces == self.faces && !self.multigrid.levels.is_empty() {
            return false;
        }
        self.multigrid = multigrid_of(&self.grid, &faces);
        self.faces = faces;
        self.multigrid_work = Work::default();
        true
    }

    /// Whether grass slows this wind: two-way coupling with a drag, and
    /// grass coupled (a canopy unit set).
    pub fn is_coupled(&self, settings: &WindSettings) -> bool {
        settings.effective_canopy_drag() > 0.0 && self.canopy_unit > 0.0
    }

    /// One full step of length `dt` (s): the mean wind's (the
    /// turbulence the last step added taken off first), then this step's
    /// turbulence added.
    pub fn step(&mut self, settings: &WindSettings, dt: f32) {
        self.take_off_turbulence();
        self.add_forces(settings, dt);
        let drag = if self.is_coupled(settings) {
            settings.effective_canopy_drag()
        } else {
            0.0
        };
        self.advect(dt, drag, settings.inflow.as_ref(), settings.advection);
        // Among solids the modes' flow runs into them: the projection
        // turns it around them as it turns the mean wind. Without, the
        // modes are divergence-free as they are, and added after it.
        let among_solids = self.solid.contains(&true);
        if among_solids {
            self.add_turbulence(settings, dt);
        }
        self.compute_divergence();
        match settings.solver {
            PressureSolver::Jacobi => self.solve_pressure(settings.jacobi_iterations),
            PressureSolver::Multigrid => self.solve_pressure_multigrid(settings.v_cycles),
        }
        self.subtract_gradient();
        self.free_slip_under_ground();
        if !among_solids {
            self.add_turbulence(settings, dt);
        }
        self.time += dt;
    }

    /// The free and buried faces without what the last step's turbulence
    /// added (in the GPU's forces kernel).
    fn take_off_turbulence(&mut self) {
        for axis in 0..3 {
            for (idx, kind) in self.faces[axis].iter().enumerate() {
                if matches!(kind, FaceKind::Free | FaceKind::Buried) {
                    self.vel[axis][idx] -= self.turbulence_added[axis][idx];
                }
            }
        }
    }

    /// Kernel 7, with turbulence (src/model/turbulence.rs): the modes
    /// carried on by this step, every free and inflow face gains the
    /// field at the step's end, and keeps what it gained (an inflow face
    /// is set anew by the next step's forces). A buried face holds the air
    /// above's value, turbulence and all (`free_slip_under_ground`).
    pub fn add_turbulence(&mut self, settings: &WindSettings, dt: f32) {
        let (Some(field), Some(_)) = (&mut self.turbulence, &settings.turbulence) else {
            return;
        };
        field.advance(
            settings.turbulence_convection(),
            settings.turbulence_sigma(),
            dt,
        );
        self.add_turbulence_now(settings);
    }

    /// Every face not a wall gains the turbulence's field as its modes
    /// stand now, and keeps what it gained (`turbulence_added`); so do the
    /// walls on the grid's sides across an axis the modes are not
    /// mirrored across, before a cell of air (a moving window's sides
    /// along the wind): there
    /// the field's normal component is not zero, and holding it at zero
    /// would leave a layer of cells diverging. The mean flow stays
    /// walled: the next step's forces set those faces to zero again.
    pub(super) fn add_turbulence_now(&mut self, settings: &WindSettings) {
        let (Some(field), Some(_)) = (&self.turbulence, &settings.turbulence) else {
            return;
        };
        let records = field.records(settings.turbulence_sigma());
        self.subgrid_turbulence = field.subgrid_records(settings.turbulence_sigma());
        let (grid, solid) = (&self.grid, &self.solid);
        let n = grid.cells;
        for axis in 0..3 {
            // A side's face before a cell of air (not one walled by an
            // obstacle or the ground at the side).
            let open_side = |f: [u32; 3]| {
                let mut c = f;
                c[axis] = c[axis].min(n[axis] - 1);
                axis != 1
                    && !field.is_mirrored(axis)
                    && (f[axis] == 0 || f[axis] == n[axis])
                    && !solid[grid.cell_index(c[0], c[1], c[2])]
            };
            for (idx, f) in self.grid.each_face(axis) {
                let kind = self.faces[axis][idx];
                if kind == FaceKind::Buried || (kind == FaceKind::Wall && !open_side(f)) {
                    self.turbulence_added[axis][idx] = 0.0;
                    continue;
                }
                let q = TurbulenceField::face_point(axis, f);
                let u = field.at(&records, axis, q);
                self.vel[axis][idx] += u;
                self.turbulence_added[axis][idx] = u;
            }
        }
    }

    /// Kernel 6, with terrain: each buried face (a horizontal component
    /// between two cells under the ground) takes the value of the first
    /// free face above it in its column. Only the samplers read these
    /// ghost values (advection's trace and a blade tip's wind): without
    /// them the zeros under the ground would be interpolated into the air
    /// above the staircase, a numerical no-slip wall that thickens
    /// downwind and lifts the flow over a hill (docs/physics.md, wind over
    /// a ridge). No pressure, divergence or projection term reads them.
    pub fn free_slip_under_ground(&mut self) {
        for axis in [0, 2] {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Buried {
                    continue;
                }
                self.vel[axis][idx] = (j + 1..self.grid.cells.y)
                    .map(|up| self.grid.face_index(axis, i, up, k))
                    .find(|&above| self.faces[axis][above] == FaceKind::Free)
                    .map_or(0.0, |above| self.vel[axis][above]);
            }
        }
    }

    /// Kernel 1: every free face gains dt * f of every source; inflow faces
    /// take the inflow velocity; walls hold zero.
    ///
    /// The colliders are moving obstacles (ours), by direct forcing: a free
    /// face inside one takes its velocity (the first in scene order that
    /// holds it). The projection then turns the air around it, as around
    /// the fixed solids; unlike theirs, these faces stay free, so the
    /// multigrid hierarchy is built once. What is left flowing through a
    /// collider is measured in tests/wind_cpu.rs (docs/physics.md).
    pub fn add_forces(&mut self, settings: &WindSettings, dt: f32) {
        let t = self.time;
        let moving: Vec<ColliderState> = settings.colliders.iter().map(|c| c.at(t)).collect();
        let sources: Vec<(Vec3, Vec3, f32, f32)> = settings
            .sources
            .iter()
            .map(|s| {
                let (p, d, st) = s.at(t);
                (p, d, st, s.radius)
            })
            .collect();
        let inflow = settings.inflow.as_ref();
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                match self.faces[axis][idx] {
                    FaceKind::Wall => self.vel[axis][idx] = 0.0,
                    // Holds the ghost value `free_slip_under_ground` gave it.
                    FaceKind::Buried => {}
                    FaceKind::Inflow => {
                        let inflow = inflow.expect("inflow faces exist only with an inflow");
                        let x = self.grid.face_position(axis, i, j, k);
                        self.vel[axis][idx] = inflow.velocity_at(axis, &self.grid, x, t);
                    }
                    FaceKind::Free => {
                        let x = self.grid.face_position(axis, i, j, k);
                        let mut a = 0.0;
                        for &(p, dir, strength, radius) in &sources {
                            a += strength * dir[axis] * falloff(x.distance(p), radius);
                        }
                        self.vel[axis][idx] += dt * a;
                        if let Some(c) = moving.iter().find(|c| c.distance(x).0 < 0.0) {
                            self.vel[axis][idx] = c.velocity[axis];
                        }
                    }
                }
            }
        }
    }

    /// Trilinear sample of component `axis` at world position `x`, clamped
    /// to the component's sample lattice.
    pub fn sample_component(&self, vel: &[f32], axis: usize, x: Vec3) -> f32 {
        let (at, f) = self.stencil(axis, x);
        let at = at.map(|i| vel[i]);
        let c00 = at[0] * (1.0 - f.x) + at[1] * f.x;
        let c10 = at[2] * (1.0 - f.x) + at[3] * f.x;
        let c01 = at[4] * (1.0 - f.x) + at[5] * f.x;
        let c11 = at[6] * (1.0 - f.x) + at[7] * f.x;
        let c0 = c00 * (1.0 - f.y) + c10 * f.y;
        let c1 = c01 * (1.0 - f.y) + c11 * f.y;
        c0 * (1.0 - f.z) + c1 * f.z
    }

    /// The least and greatest of the eight samples `sample_component`
    /// interpolates at `x`: the range MacCormack's corrector is clamped to.
    /// Along an axis where the point lies within `RANGE_SNAP` of a
    /// lattice plane, only that plane's samples count: there the
    /// interpolation is continuous but the eight samples are not (a hair
    /// below the plane takes the row beyond it), and a back trace along a
    /// component near zero lands there, where the GPU's rounding and the
    /// CPU's would pick different rows, and a wind turned a quarter
    /// another row than the unturned one.
    pub fn sample_range(&self, vel: &[f32], axis: usize, x: Vec3) -> (f32, f32) {
        let g = self.lattice_point(axis, x);
        let d = self.grid.face_dims(axis);
        let on = (g - g.round()).abs().cmplt(Vec3::splat(RANGE_SNAP));
        let i0 = Vec3::select(on, g.round(), g.floor()).as_uvec3().min(d - 1);
        let i1 = UVec3::select(on, i0, (i0 + 1).min(d - 1));
        self.corners(axis, i0, i1)
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &i| {
                (lo.min(vel[i]), hi.max(vel[i]))
            })
    }

    /// The eight samples of component `axis` around `x` (x fastest, then
    /// y, then z) and the fractions between them, clamped to the lattice.
    fn stencil(&self, axis: usize, x: Vec3) -> ([usize; 8], Vec3) {
        let d = self.grid.face_dims(axis);
        let g = self.lattice_point(axis, x);
        let i0 = g.floor().as_uvec3().min(d - 1);
        let i1 = (i0 + 1).min(d - 1);
        (self.corners(axis, i0, i1), g - i0.as_vec3())
    }

    /// `x` in the sample lattice of component `axis`, clamped to it.
    fn lattice_point(&self, axis: usize, x: Vec3) -> Vec3 {
        let d = self.grid.face_dims(axis);
        let mut offset = Vec3::splat(0.5);
        offset[axis] = 0.0;
        let g = (x - self.grid.origin) / self.grid.cell - offset;
        g.clamp(Vec3::ZERO, (d - 1).as_vec3())
    }

    /// The face indices of component `axis`'s samples at the corners
    /// `i0` and `i1` span (x fastest, then y, then z).
    fn corners(&self, axis: usize, i0: UVec3, i1: UVec3) -> [usize; 8] {
        let at = |i: u32, j: u32, k: u32| self.grid.face_index(axis, i, j, k);
        [
            at(i0.x, i0.y, i0.z),
            at(i1.x, i0.y, i0.z),
            at(i0.x, i1.y, i0.z),
            at(i1.x, i1.y, i0.z),
            at(i0.x, i0.y, i1.z),
            at(i1.x, i0.y, i1.z),
            at(i0.x, i1.y, i1.z),
            at(i1.x, i1.y, i1.z),
        ]
    }

    /// The velocity at the centre of cell (i, j, k): each component the
    /// mean of the cell's two faces across its axis.
    pub fn cell_velocity(&self, i: u32, j: u32, k: u32) -> Vec3 {
        let mean = |axis: usize| {
            let mut hi = [i, j, k];
            hi[axis] += 1;
            let a = self.vel[axis][self.grid.face_index(axis, i, j, k)];
            let b = self.vel[axis][self.grid.face_index(axis, hi[0], hi[1], hi[2])];
            0.5 * (a + b)
        };
        Vec3::new(mean(0), mean(1), mean(2))
    }

    /// The cell holding the world point `x`, or None outside the grid.
    pub fn cell_at(&self, x: Vec3) -> Option<usize> {
        let g = ((x - self.grid.origin) / self.grid.cell).floor();
        let inside = g.cmpge(Vec3::ZERO).all() && g.cmplt(self.grid.cells.as_vec3()).all();
        inside.then(|| {
            let g = g.as_uvec3();
            self.grid.cell_index(g.x, g.y, g.z)
        })
    }

    /// Wind velocity at a world position (what a blade tip samples).
    pub fn sample(&self, x: Vec3) -> Vec3 {
        Vec3::new(
            self.sample_component(&self.vel[0], 0, x),
            self.sample_component(&self.vel[1], 1, x),
            self.sample_component(&self.vel[2], 2, x),
        )
    }

    /// The wind a blade's tip at `x` feels: the grid's (`sample`) and the
    /// turbulence's modes finer than the grid summed there
    /// (glsl/grass/step.glsl the same).
    pub fn felt(&self, x: Vec3) -> Vec3 {
        let wind = self.sample(x);
        if self.subgrid_turbulence.is_empty() {
            return wind;
        }
        let at = x - self.grid.origin;
        wind + super::turbulence::velocity_at(&self.subgrid_turbulence, at)
    }

    /// Kernel 2: advection. Each free face traces back by dt along the
    /// velocity there and takes the value it finds (semi-Lagrangian, the
    /// paper's); MacCormack's corrector (`wind.advection = "maccormack"`,
    /// the default) traces that result forward again, adds half the
    /// difference from the value it started with (the first-order step's
    /// error, so second order), and clamps the sum to the range of the
    /// eight values the back trace interpolated (no new extremes). Then the canopy drag with
    /// coefficient `canopy_drag` (0: none) slows it, implicitly, by the
    /// speed at the face before advection: u' = u / (1 + dt C_d a |u|)
    /// (src/model/canopy.rs).
    ///
    /// Air traced back beyond an inflow's entry side comes from outside:
    /// a horizontal component traced across the other horizontal axis's
    /// entry side takes the inflow's (`Inflow::entering`), uncorrected;
    /// one traced across its own axis's finds the entry faces in its
    /// lattice.
    pub fn advect(
        &mut self,
        dt: f32,
        canopy_drag: f32,
        inflow: Option<&Inflow>,
        scheme: Advection,
    ) {
        let src = self.vel.clone();
        // The semi-Lagrangian step of every free face (the predictor),
        // whether it came from outside, and the velocity it traced with.
        let mut predicted = src.clone();
        let mut traced: [Vec<Option<(Vec3, bool)>>; 3] =
            [0, 1, 2].map(|a| vec![None; src[a].len()]);
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Free {
                    continue;
                }
                let x = self.grid.face_position(axis, i, j, k);
                let v = Vec3::new(
                    self.sample_component(&src[0], 0, x),
                    self.sample_component(&src[1], 1, x),
                    self.sample_component(&src[2], 2, x),
                );
                let back = x - dt * v;
                let entering = inflow.and_then(|i| i.entering(axis, &self.grid, back, self.time));
                predicted[axis][idx] =
                    entering.unwrap_or_else(|| self.sample_component(&src[axis], axis, back));
                traced[axis][idx] = Some((v, entering.is_some()));
            }
        }
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                let Some((v, entered)) = traced[axis][idx] else {
                    continue;
                };
                let mut u = predicted[axis][idx];
                if scheme == Advection::Maccormack && !entered {
                    let x = self.grid.face_position(axis, i, j, k);
                    let again = self.sample_component(&predicted[axis], axis, x + dt * v);
                    let (lo, hi) = self.sample_range(&src[axis], axis, x - dt * v);
                    // max then min: a NaN stays a NaN rather than a panic.
                    u = (u + 0.5 * (src[axis][idx] - again)).max(lo).min(hi);
                }
                if canopy_drag > 0.0 {
                    let a = self.face_canopy_density(axis, [i, j, k]);
                    u /= 1.0 + dt * canopy_drag * a * v.length();
                }
                self.vel[axis][idx] = u;
            }
        }
    }

    /// The frontal area per unit volume (1/m) at face `f` of component
    /// `axis`: the mean of the two cells it parts (the one inside, at the
    /// grid's sides), from the counts as the GPU reads them:
    /// (c_left + c_right) * (unit / 2 / cell volume).
    pub fn face_canopy_density(&self, axis: usize, f: [u32; 3]) -> f32 {
        let n = self.grid.cells[axis];
        let mut left = f;
        left[axis] = f[axis].max(1) - 1;
        let mut right = f;
        right[axis] = f[axis].min(n - 1);
        let count = |c: [u32; 3]| self.canopy[self.grid.cell_index(c[0], c[1], c[2])] as f32;
        (count(left) + count(right)) * self.canopy_density_per_count()
    }

    /// unit / 2 / cell volume: what one count on each side of a face adds
    /// to the face's frontal area per unit volume (1/m).
    pub fn canopy_density_per_count(&self) -> f32 {
        self.canopy_unit * 0.5 / self.grid.cell.element_product()
    }

    /// Kernel 3: divergence of each fluid cell, sum over axes of (out - in) / h.
    pub fn compute_divergence(&mut self) {
        for (c, [i, j, k]) in self.grid.each_cell() {
            self.divergence[c] = if self.solid[c] {
                0.0
            } else {
                self.cell_divergence(i, j, k)
            };
        }
    }

    pub fn cell_divergence(&self, i: u32, j: u32, k: u32) -> f32 {
        let mut div = 0.0;
        for axis in 0..3 {
            let mut hi = [i, j, k];
            hi[axis] += 1;
            let a = self.vel[axis][self.grid.face_index(axis, i, j, k)];
            let b = self.vel[axis][self.grid.face_index(axis, hi[0], hi[1], hi[2])];
            div += (b - a) / self.grid.cell[axis];
        }
        div
    }

    /// Largest |divergence| over the fluid cells.
    pub fn max_divergence(&self) -> f32 {
        self.grid
            .each_cell()
            .filter(|&(c, _)| !self.solid[c])
            .map(|(_, [i, j, k])| self.cell_divergence(i, j, k).abs())
            .fold(0.0, f32::max)
    }

    /// Root mean square divergence over the fluid cells: the max norm
    /// follows the slowest Jacobi modes, this the field as a whole.
    pub fn rms_divergence(&self) -> f32 {
        let (sum, n) = self
            .grid
            .each_cell()
            .filter(|&(c, _)| !self.solid[c])
            .map(|(_, [i, j, k])| (self.cell_divergence(i, j, k) as f64).powi(2))
            .fold((0.0, 0usize), |(s, n), d| (s + d, n + 1));
        (sum / n.max(1) as f64).sqrt() as f32
    }

    /// Kernel 4: Jacobi iterations for the pressure (with dt/rho folded in):
    /// sum over free faces of (p_nb - p) / h^2 = div. Across a wall face
    /// the term drops (Neumann); outside an open side p = 0 (Dirichlet).
    ///
    /// Warm start (ours): the iterations begin from the previous step's
    /// pressure, so the solve converges across steps and the pressure
    /// reaches across the whole grid although each step runs only a few
    /// dozen iterations.
    pub fn solve_pressure(&mut self, iterations: u32) {
        let mut next = self.pressure.clone();
        for _ in 0..iterations {
            for (c, [i, j, k]) in self.grid.each_cell() {
                next[c] = if self.solid[c] {
                    0.0
                } else {
                    self.jacobi_cell(i, j, k)
                };
            }
            std::mem::swap(&mut self.pressure, &mut next);
        }
    }

    /// Kernel 4 of the multigrid solver: `cycles` V-cycles on the
    /// same equation, from zero pressure. (Each step's pressure is that
    /// step's correction; starting from the previous one helps in steady
    /// wind but leaves most of the divergence after a change such as a
    /// gust, where a start from zero leaves the same share every step.)
    pub fn solve_pressure_multigrid(&mut self, cycles: u32) {
        let b = Multigrid::rhs_from_divergence(self.grid.cell, &self.divergence);
        self.pressure.fill(0.0);
        for _ in 0..cycles {
            self.multigrid
                .v_cycle(&mut self.pressure, &b, &mut self.multigrid_work);
        }
    }

    fn jacobi_cell(&self, i: u32, j: u32, k: u32) -> f32 {
        let n = self.grid.cells;
        let mut sum = 0.0;
        let mut weight = 0.0;
        for axis in 0..3 {
            let inv_h2 = 1.0 / (self.grid.cell[axis] * self.grid.cell[axis]);
            for side in [0u32, 1] {
                // The face between this cell and the neighbour on `side`.
                let mut f = [i, j, k];
                f[axis] += side;
                // Fixed faces (walls, inflow): no pressure term (Neumann).
                if self.faces[axis][self.grid.face_index(axis, f[0], f[1], f[2])] != FaceKind::Free
                {
                    continue;
                }
                let mut nb = [i as i64, j as i64, k as i64];
                nb[axis] += if side == 1 { 1 } else { -1 };
                let outside = nb[axis] < 0 || nb[axis] >= n[axis] as i64;
                let p_nb = if outside {
                    0.0
                } else {
                    self.pressure[self
                        .grid
                        .cell_index(nb[0] as u32, nb[1] as u32, nb[2] as u32)]
                };
                sum += p_nb * inv_h2;
                weight += inv_h2;
            }
        }
        if weight == 0.0 {
            return 0.0;
        }
        (sum - self.divergence[self.grid.cell_index(i, j, k)]) / weight
    }

    /// Kernel 5: subtract the pressure gradient from every free face,
    /// (p_right - p_left) / h, with p = 0 outside an open side.
    pub fn subtract_gradient(&mut self) {
        let n = self.grid.cells;
        for axis in 0..3 {
            for (idx, f) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Free {
                    continue;
                }
                let p_right = if f[axis] < n[axis] {
                    self.pressure[self.grid.cell_index(f[0], f[1], f[2])]
                } else {
                    0.0
                };
                let p_left = if f[axis] > 0 {
                    let mut l = f;
                    l[axis] -= 1;
                    self.pressure[self.grid.cell_index(l[0], l[1], l[2])]
                } else {
                    0.0
                };
                self.vel[axis][idx] -= (p_right - p_left) / self.grid.cell[axis];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_iterators_number_samples_as_storage_does() {
        let grid = WindGrid::new(UVec3::new(3, 2, 4), Vec3::ZERO, Vec3::ONE).unwrap();
        for axis in 0..3 {
            let d = grid.face_dims(axis);
            let all: Vec<_> = grid.each_face(axis).collect();
            assert_eq!(all.len(), (d.x * d.y * d.z) as usize);
            for (idx, [i, j, k]) in all {
                assert_eq!(idx, grid.face_index(axis, i, j, k));
            }
        }
        for (c, [i, j, k]) in grid.each_cell() {
            assert_eq!(c, grid.cell_index(i, j, k));
        }
    }
}
