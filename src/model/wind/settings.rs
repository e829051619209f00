//! The wind's settings: the pressure solver, the advection, the coupling
//! with the grass and the rest of a scene's `[wind]` section, checked
//! against the grid.

use glam::Vec3;

use super::{Inflow, Obstacle, Side, Turbulence, WindGrid, WindSource};
use crate::error::Result;
use crate::model::contact::Collider;
use crate::model::terrain::Terrain;

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

/// How the GPU runs a red-black Gauss-Seidel sweep of the multigrid's
/// fine levels (glsl/wind/mg_smooth.comp, mg_sweep.comp). The two give the
/// same pressure: only the dispatches and the arithmetic differ.
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
pub enum Sweep {
    /// Fused on a GPU, split on a CPU device (lavapipe), where a dispatch
    /// costs next to nothing and the cells swept twice cost their time.
    #[default]
    Auto,
    /// Both colours in one dispatch: each workgroup sweeps a tile and
    /// works the red cells of one cell around it out again, so a
    /// V-cycle's dispatches fall from 45 to 29 on the paper's grid.
    Fused,
    /// One dispatch a colour.
    Split,
}

impl Sweep {
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Auto => "auto",
            Sweep::Fused => "fused",
            Sweep::Split => "split",
        }
    }
}

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
    /// The most V-cycles a step runs when `solver` is multigrid
    /// (default 7).
    pub v_cycles: u32,
    /// With multigrid, the V-cycles stop once the rms residual is at most
    /// this share of the right-hand side's: the share of the step's
    /// divergence the projection may leave (`solve_pressure_multigrid`).
    #[serde(default = "default_pressure_tolerance")]
    pub pressure_tolerance: f32,
    /// How the GPU runs the multigrid's sweeps (`Sweep`).
    #[serde(default)]
    pub sweep: Sweep,
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
            pressure_tolerance: DEFAULT_PRESSURE_TOLERANCE,
            sweep: Sweep::default(),
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
pub use crate::model::multigrid::{DEFAULT_PRESSURE_TOLERANCE, DEFAULT_V_CYCLES};

fn default_pressure_tolerance() -> f32 {
    DEFAULT_PRESSURE_TOLERANCE
}

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
