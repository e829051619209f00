//! `meadow wind` as a library call: the wind solver on the GPU, timed per
//! step with timestamp queries, with pictures of two slices and the
//! divergence before and after projection. With two-way coupling the
//! scene's grass steps between the wind steps (untimed), since it is what
//! slows the air.

use std::path::Path;

use glam::Vec3;

use crate::analysis::stats::rms_over_fluid;
use crate::commands::on_gpu;
use crate::compute::{Simulation, WindPass};
use crate::error::Result;
use crate::frame::timing::median_p95;
use crate::frame::BladeBuffer;
use crate::gpu::query::TimestampQueries;
use crate::gpu::{CommandPool, DependsOn, DeviceMemory, Gpu, GpuOptions, ValidationReport};
use crate::model::multigrid::SolveCounts;
use crate::model::wind::{
    Advection, Coupling, PressureSolver, Sweep, WindField, WindGrid, WindSettings,
};
use crate::report::claim::OutputClaim;
use crate::report::files;
pub use crate::report::wind::{AdvectionTiming, SolverTiming, TurbulenceTiming};
use crate::report::wind_slices::{self, Outlines, Slice};
use crate::scene::{field, Scene};

/// Steps recorded into one submission (and timed with one query pool).
const STEPS_PER_SUBMIT: u32 = 100;

/// Where the wind grid lies: the centre of cell (i, j, k) is
/// origin + (i + 0.5, j + 0.5, k + 0.5) * cell_size (metres, y up).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct GridReport {
    pub origin: [f32; 3],
    pub cell_size: [f32; 3],
    pub cells: [u32; 3],
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct WindReport {
    pub scene: String,
    pub device: String,
    /// The device memory the run's allocations held at the end and at
    /// most.
    pub device_memory: DeviceMemory,
    pub cells: [u32; 3],
    /// The grid wind_field.npy is sampled on, in the world's coordinates
    /// (a cover's window under the camera where the scene starts).
    pub grid: GridReport,
    /// How the pressure was solved, and with how many iterations or cycles.
    pub solver: PressureSolver,
    pub jacobi_iterations: u32,
    /// The most V-cycles a step may run (multigrid).
    pub v_cycles: u32,
    /// The share of a step's divergence the multigrid may leave.
    pub pressure_tolerance: f32,
    /// V-cycles per step over the run, median and most (multigrid; None
    /// with Jacobi).
    pub v_cycles_median: Option<u32>,
    pub v_cycles_most: Option<u32>,
    /// The wind step's dispatches that ran workgroups, at the median
    /// V-cycles, and those it records (the V-cycles switched off on zero
    /// workgroups included).
    pub dispatches_per_step: u32,
    pub dispatches_recorded: u32,
    /// How the multigrid's sweeps ran: "fused" (both colours in one
    /// dispatch) or "split" (`wind.sweep`, "auto" resolved on the device;
    /// None with Jacobi).
    pub sweep: Option<Sweep>,
    /// Whether the grass slowed the wind (two-way: its grass stepped too).
    pub coupling: Coupling,
    /// How the advection carried the velocity.
    pub advection: Advection,
    pub steps: u32,
    pub dt: f32,
    pub max_speed: f32,
    /// Largest |divergence| of the last step's advected field (before projection).
    pub max_divergence_before: f32,
    /// Largest |divergence| of the projected field.
    pub max_divergence_after: f32,
    /// RMS divergence over the fluid cells, before and after projection.
    pub rms_divergence_before: f32,
    pub rms_divergence_after: f32,
    /// GPU time of one solver step (timestamp queries), median and p95, ms;
    /// None where the device has no timestamps.
    pub step_ms_median: Option<f64>,
    pub step_ms_p95: Option<f64>,
    /// Both solvers over the same steps (multigrid, then Jacobi).
    pub solvers: Vec<SolverTiming>,
    /// With `wind.turbulence`: the step with it and without it, over the
    /// same steps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turbulence_cost: Option<TurbulenceTiming>,
    /// The step with each advection (MacCormack's, the paper's
    /// semi-Lagrangian) over the same steps.
    pub advection_cost: AdvectionTiming,
    pub warnings: Vec<String>,
    pub validation: ValidationReport,
}

/// The steps `wind_to_dir` runs for `steps` of the scene's.
pub fn steps_run(scene: &Scene, steps: u32) -> u64 {
    let runs = 4 + scene.wind.turbulence.is_some() as u64;
    runs * steps as u64
}

/// The files `wind_to_dir` writes.
pub const WIND_OUTPUTS: [&str; 4] = [
    "wind_horizontal.svg",
    "wind_vertical.svg",
    "wind_field.npy",
    "wind_report.json",
];

/// Runs the wind and writes its two slices and wind_report.json into
/// `out_dir`, replacing only an earlier run's (`overwrite`: any file of
/// those names; `report::claim`). `progress` hears of each submission's
/// steps as they finish: `steps_run(scene, steps)` in all (the scene's,
/// each solver's for the comparison, with the other advection, and without
/// turbulence for its cost).
pub fn wind_to_dir(
    scene: &Scene,
    steps: u32,
    gpu_options: &GpuOptions,
    out_dir: &Path,
    overwrite: bool,
    progress: &mut dyn FnMut(u32),
) -> Result<WindReport> {
    let grid = scene.wind_grid()?;
    let settings = scene.wind_settings();
    let warnings = settings.check(&grid)?;
    files::ensure_dir(out_dir)?;
    let planned: Vec<String> = WIND_OUTPUTS.iter().map(|s| s.to_string()).collect();
    let claim = OutputClaim::new(out_dir, &planned, overwrite)?;
    // wind_field.npy: three float32s per cell.
    let cells = grid.cells.x as u64 * grid.cells.y as u64 * grid.cells.z as u64;
    claim.ensure_room(
        cells * 12,
        &format!("the wind field of {cells} cells (wind_field.npy)"),
    )?;
    let (mut report, validation) = on_gpu(gpu_options, |gpu| {
        run(gpu, scene, grid, &settings, steps, &claim, progress)
    })?;
    report.warnings = warnings;
    // The projection should remove most of the divergence advection made;
    // when it did not, the field is not incompressible and the user should
    // know why and what to change.
    // Below f32's rounding floor there is nothing left to remove.
    if report.rms_divergence_after > 0.5 * report.rms_divergence_before
        && report.rms_divergence_after > grid.divergence_floor(report.max_speed)
    {
        let solve =
            crate::report::wind::describe(report.solver, report.jacobi_iterations, report.v_cycles);
        let fix = match report.solver {
            PressureSolver::Jacobi => "use multigrid (wind.solver = \"multigrid\", --v-cycles 7) or raise them (--jacobi-iterations, wind.jacobi_iterations; docs/physics.md measures both)",
            PressureSolver::Multigrid => "raise them (--v-cycles, wind.v_cycles; docs/physics.md)",
        };
        report.warnings.push(format!(
            "the projection left {:.0}% of the divergence (rms {:.3e} -> {:.3e} 1/s) with {solve}; {fix}",
            100.0 * report.rms_divergence_after / report.rms_divergence_before.max(f32::MIN_POSITIVE),
            report.rms_divergence_before,
            report.rms_divergence_after,
        ));
    }
    report.validation = validation;
    claim.write_json("wind_report.json", &report)?;
    report.validation.check()?;
    Ok(report)
}

/// The wind after `steps` steps on the GPU, with each step's GPU time (ms;
/// empty where the device has no timestamps).
struct Stepped {
    field: WindField,
    times: Vec<f64>,
    /// Divergence of the last step's advected field, before projection.
    before: Vec<f32>,
    /// The multigrid's solves (None with Jacobi).
    solve: Option<SolveCounts>,
    /// A step's dispatches that ran workgroups (at the median V-cycles)
    /// and those it recorded.
    dispatches: [u32; 2],
    /// How the multigrid's sweeps ran (None with Jacobi).
    sweep: Option<Sweep>,
}

/// The wind alone, or with two-way coupling the wind with the scene's grass
/// stepping between its steps (the grass is what slows it).
// One per run, never moved: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
enum Stepper {
    Wind(WindPass),
    /// The simulation, whose grass writes the blade buffer it keeps.
    Coupled(DependsOn<Simulation, BladeBuffer>),
}

impl Stepper {
    fn new(gpu: &Gpu, commands: &CommandPool, scene: &Scene) -> Result<Self> {
        let grid = scene.wind_grid()?;
        if scene.wind.coupling == Coupling::OneWay {
            let pass = WindPass::new(gpu, commands, grid, &scene.wind_settings(), 0.0)?;
            return Ok(Stepper::Wind(pass));
        }
        let rest = scene.field()?;
        let blades = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed)?;
        let vertices =
            BladeBuffer::uninitialised(gpu, "wind command blade vertices", blades.len())?;
        let simulation = Simulation::new(gpu, commands, scene, &blades, vertices.buffer())?;
        Ok(Stepper::Coupled(DependsOn::new(simulation, vertices)))
    }

    /// Records the wind half of step `index`.
    fn record_wind(&mut self, rec: &crate::gpu::Recording, index: u32, dt: f32) {
        match self {
            Stepper::Wind(pass) => pass.record_step(rec, index as f32 * dt, dt),
            Stepper::Coupled(simulation) => simulation.record_wind_step(rec),
        }
    }

    /// Records the grass half of the step, if the grass is coupled.
    fn record_grass(&mut self, rec: &crate::gpu::Recording) {
        if let Stepper::Coupled(simulation) = self {
            simulation.record_grass_step(rec);
        }
    }

    fn wind(&self) -> &WindPass {
        match self {
            Stepper::Wind(pass) => pass,
            Stepper::Coupled(simulation) => simulation.wind(),
        }
    }
}

/// Runs `steps` steps of the scene's wind, telling `progress` of each
/// submission's steps as they finish.
fn run_steps(
    gpu: &Gpu,
    commands: &CommandPool,
    scene: &Scene,
    steps: u32,
    progress: &mut dyn FnMut(u32),
) -> Result<Stepped> {
    let dt = scene.wind.dt;
    let mut stepper = Stepper::new(gpu, commands, scene)?;
    let timestamps = TimestampQueries::new(gpu, STEPS_PER_SUBMIT, "wind step timestamps")?;
    let mut times = Vec::new();
    let mut done = 0;
    while done < steps {
        let batch = (steps - done).min(STEPS_PER_SUBMIT);
        let rec = commands.begin()?;
        if let Some(t) = &timestamps {
            t.reset(&rec);
        }
        for n in 0..batch {
            if let Some(t) = &timestamps {
                t.stamp(&rec, n, false);
            }
            stepper.record_wind(&rec, done + n, dt);
            if let Some(t) = &timestamps {
                t.stamp(&rec, n, true);
            }
            stepper.record_grass(&rec);
        }
        rec.submit_and_wait("wind steps")?;
        if let Some(t) = &timestamps {
            times.extend(t.read_ms(batch)?);
        }
        done += batch;
        progress(batch);
    }
    let mut field = WindField::new(scene.wind_grid()?, &scene.wind_settings());
    field.vel = stepper.wind().read_velocity(gpu, commands)?;
    let before = stepper.wind().read_divergence(gpu, commands)?;
    let solve = stepper.wind().read_solve_counts(gpu, commands)?;
    let every = stepper.wind().step_dispatches(None);
    Ok(Stepped {
        field,
        times,
        before,
        solve,
        dispatches: solve.map_or([every; 2], |s| [s.dispatches_median, s.dispatches_recorded]),
        sweep: solve.map(|_| stepper.wind().sweep()),
    })
}

/// The scene's wind run `steps` steps with each solver (its V-cycles, its
/// Jacobi iterations), multigrid first; `progress` hears of the steps.
pub fn compare_solvers(
    gpu: &Gpu,
    scene: &Scene,
    steps: u32,
    progress: &mut dyn FnMut(u32),
) -> Result<Vec<SolverTiming>> {
    let commands = CommandPool::new(gpu, "wind solver comparison commands")?;
    let mut timings = Vec::new();
    for solver in [PressureSolver::Multigrid, PressureSolver::Jacobi] {
        let mut scene = scene.clone();
        scene.wind.solver = solver;
        let settings = scene.wind_settings();
        let run = run_steps(gpu, &commands, &scene, steps, progress)?;
        let timing = median_p95(&run.times);
        timings.push(SolverTiming {
            solver,
            iterations: match solver {
                PressureSolver::Multigrid => settings.v_cycles,
                PressureSolver::Jacobi => settings.jacobi_iterations,
            },
            steps,
            step_ms_median: timing.map(|t| t.0),
            step_ms_p95: timing.map(|t| t.1),
            rms_divergence_before: rms_over_fluid(&run.before, &run.field.solid) as f32,
            rms_divergence_after: run.field.rms_divergence(),
        });
    }
    Ok(timings)
}

/// With turbulence, the scene's wind step timed without it over the same
/// number of steps, beside `with` (the steps' GPU times with it, ms).
fn turbulence_cost(
    gpu: &Gpu,
    scene: &Scene,
    steps: u32,
    with: &[f64],
    progress: &mut dyn FnMut(u32),
) -> Result<Option<TurbulenceTiming>> {
    if scene.wind.turbulence.is_none() {
        return Ok(None);
    }
    let mut calm = scene.clone();
    calm.wind.turbulence = None;
    let commands = CommandPool::new(gpu, "wind turbulence cost commands")?;
    let without = run_steps(gpu, &commands, &calm, steps, progress)?;
    let (with, without) = (median_p95(with), median_p95(&without.times));
    Ok(Some(TurbulenceTiming {
        steps,
        step_ms_median_with: with.map(|t| t.0),
        step_ms_median_without: without.map(|t| t.0),
        ratio: with.zip(without).map(|(w, wo)| w.0 / wo.0),
    }))
}

/// The scene's wind step timed with the advection it does not use over the
/// same number of steps, beside `own` (the steps' GPU times with its own,
/// ms).
fn advection_cost(
    gpu: &Gpu,
    scene: &Scene,
    steps: u32,
    own: &[f64],
    progress: &mut dyn FnMut(u32),
) -> Result<AdvectionTiming> {
    let mut other = scene.clone();
    other.wind.advection = match scene.wind.advection {
        Advection::Maccormack => Advection::SemiLagrangian,
        Advection::SemiLagrangian => Advection::Maccormack,
    };
    let commands = CommandPool::new(gpu, "wind advection cost commands")?;
    let run = run_steps(gpu, &commands, &other, steps, progress)?;
    let median = |times: &[f64]| median_p95(times).map(|t| t.0);
    let (own, other) = (median(own), median(&run.times));
    Ok(match scene.wind.advection {
        Advection::Maccormack => AdvectionTiming::new(steps, own, other),
        Advection::SemiLagrangian => AdvectionTiming::new(steps, other, own),
    })
}

fn run(
    gpu: &Gpu,
    scene: &Scene,
    grid: WindGrid,
    settings: &WindSettings,
    steps: u32,
    claim: &OutputClaim,
    progress: &mut dyn FnMut(u32),
) -> Result<WindReport> {
    let dt = scene.wind.dt;
    let commands = CommandPool::new(gpu, "wind commands")?;
    let Stepped {
        field,
        times,
        before,
        solve,
        dispatches: [dispatches_per_step, dispatches_recorded],
        sweep,
    } = run_steps(gpu, &commands, scene, steps, progress)?;
    let max_divergence_before = before.iter().fold(0.0f32, |m, d| m.max(d.abs()));
    let rms_divergence_before = rms_over_fluid(&before, &field.solid) as f32;
    let max_speed = max_speed(&field);
    write_slices(scene, settings, &field, (steps, max_speed), claim)?;
    claim.write("wind_field.npy", &field_npy(&field))?;
    let timing = median_p95(&times);
    Ok(WindReport {
        scene: scene.name.clone(),
        device: gpu.info().name.clone(),
        device_memory: gpu.device_memory(),
        cells: grid.cells.to_array(),
        grid: GridReport {
            origin: field.grid.origin.to_array(),
            cell_size: field.grid.cell.to_array(),
            cells: field.grid.cells.to_array(),
        },
        solver: settings.solver,
        jacobi_iterations: settings.jacobi_iterations,
        v_cycles: settings.v_cycles,
        pressure_tolerance: settings.pressure_tolerance,
        v_cycles_median: solve.map(|s| s.v_cycles_median),
        v_cycles_most: solve.map(|s| s.v_cycles_most),
        dispatches_per_step,
        dispatches_recorded,
        sweep,
        coupling: settings.coupling,
        advection: settings.advection,
        steps,
        dt,
        max_speed,
        max_divergence_before,
        max_divergence_after: field.max_divergence(),
        rms_divergence_before,
        rms_divergence_after: field.rms_divergence(),
        step_ms_median: timing.map(|t| t.0),
        step_ms_p95: timing.map(|t| t.1),
        solvers: compare_solvers(gpu, scene, steps, progress)?,
        turbulence_cost: turbulence_cost(gpu, scene, steps, &times, progress)?,
        advection_cost: advection_cost(gpu, scene, steps, &times, progress)?,
        warnings: Vec::new(),
        validation: ValidationReport::default(),
    })
}

/// wind_horizontal.svg and wind_vertical.svg: the field after `steps`
/// steps, speed coloured up to `max_speed`, the solids and grass outlined;
/// the last run's files go before the first is written.
fn write_slices(
    scene: &Scene,
    settings: &WindSettings,
    field: &WindField,
    (steps, max_speed): (u32, f32),
    claim: &OutputClaim,
) -> Result<()> {
    let grass_height = scene.grass.shape.height[1];
    let center = field.grid.origin + field.grid.size() / 2.0;
    let patches = scene.grass.patches();
    let outlines = Outlines {
        ground: &settings.terrain,
        obstacles: &settings.obstacles,
        grass: &patches,
        grass_height,
    };
    let how = format!(
        "{}, {} advection, {} coupling",
        crate::report::wind::describe(
            settings.solver,
            settings.jacobi_iterations,
            settings.v_cycles
        ),
        settings.advection.name(),
        settings.coupling.name()
    );
    for (name, slice) in [
        (
            "wind_horizontal.svg",
            Slice::Horizontal {
                height: grass_height * 0.8,
            },
        ),
        ("wind_vertical.svg", Slice::Vertical { depth: center.z }),
    ] {
        let title = format!(
            "{}: {} after {:.2} s ({how})",
            scene.name,
            wind_slices::plane_name(slice, &settings.terrain),
            steps as f32 * scene.wind.dt
        );
        let svg = wind_slices::svg(field, slice, max_speed, &outlines, &title)?;
        if name == "wind_horizontal.svg" {
            // The work is done: the last run's files go.
            claim.begin()?;
        }
        claim.write(name, svg.as_bytes())?;
    }
    Ok(())
}

/// wind_field.npy: float32 of shape (nx, ny, nz, 3), the velocity at
/// each cell's centre (m/s), NaN in the solid cells (obstacles, and the
/// cells under the ground).
fn field_npy(field: &WindField) -> Vec<u8> {
    let n = field.grid.cells;
    let mut values = Vec::with_capacity(3 * field.grid.cell_count());
    for i in 0..n.x {
        for j in 0..n.y {
            for k in 0..n.z {
                let v = if field.solid[field.grid.cell_index(i, j, k)] {
                    Vec3::NAN
                } else {
                    field.cell_velocity(i, j, k)
                };
                values.extend(v.to_array());
            }
        }
    }
    crate::report::npy::f32_array(&[n.x as usize, n.y as usize, n.z as usize, 3], &values)
}

/// Largest speed at any cell centre.
fn max_speed(field: &WindField) -> f32 {
    field
        .grid
        .each_cell()
        .map(|(_, [i, j, k])| field.sample(field.grid.cell_center(i, j, k)).length())
        .fold(0.0, f32::max)
}
