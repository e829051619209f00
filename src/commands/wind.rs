//! `meadow wind` as a library call: the wind solver alone on the GPU, timed
//! per step with timestamp queries, with pictures of two slices and the
//! divergence before and after projection.

use std::path::Path;

use crate::commands::{on_gpu, write_json};
use crate::error::Result;
use crate::frame::timing::median_p95;
use crate::gpu::query::TimestampQueries;
use crate::gpu::{Commands, Gpu, GpuOptions, ValidationReport};
use crate::report::files;
pub use crate::report::wind::SolverTiming;
use crate::report::wind_slices::{self, Slice};
use crate::scene::Scene;
use crate::sim::wind::{PressureSolver, WindField, WindGrid, WindSettings};
use crate::simulate::WindPass;

/// Steps recorded into one submission (and timed with one query pool).
const STEPS_PER_SUBMIT: u32 = 100;

#[derive(Clone, Debug, serde::Serialize)]
pub struct WindReport {
    pub scene: String,
    pub device: String,
    pub cells: [u32; 3],
    /// How the pressure was solved, and with how many iterations or cycles.
    pub solver: PressureSolver,
    pub jacobi_iterations: u32,
    pub v_cycles: u32,
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
    pub warnings: Vec<String>,
    pub validation: ValidationReport,
}

pub fn wind_to_dir(
    scene: &Scene,
    steps: u32,
    gpu_options: &GpuOptions,
    out_dir: &Path,
) -> Result<WindReport> {
    let grid = scene.wind_grid()?;
    let settings = scene.wind.settings();
    let warnings = settings.check(&grid)?;
    files::ensure_dir(out_dir)?;
    let (mut report, validation) = on_gpu(gpu_options, |gpu| {
        run(gpu, scene, grid, &settings, steps, out_dir)
    })?;
    report.warnings = warnings;
    // The projection should remove most of the divergence advection made;
    // when it did not, the field is not incompressible and the user should
    // know why and what to change.
    if report.rms_divergence_after > 0.5 * report.rms_divergence_before {
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
    write_json(&out_dir.join("wind_report.json"), &report)?;
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
}

fn run_steps(
    gpu: &Gpu,
    commands: &Commands,
    grid: WindGrid,
    settings: &WindSettings,
    steps: u32,
    dt: f32,
) -> Result<Stepped> {
    let pass = WindPass::new(gpu, commands, grid, settings, 0.0)?;
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
            pass.record_step(&rec, (done + n) as f32 * dt, dt);
            if let Some(t) = &timestamps {
                t.stamp(&rec, n, true);
            }
        }
        rec.submit_and_wait("wind steps")?;
        if let Some(t) = &timestamps {
            times.extend(t.read_ms(batch)?);
        }
        done += batch;
    }
    let mut field = WindField::new(grid, settings);
    field.vel = pass.read_velocity(gpu, commands)?;
    let before = pass.read_divergence(gpu, commands)?;
    Ok(Stepped {
        field,
        times,
        before,
    })
}

/// RMS of a cell field over the fluid cells.
fn rms_over_fluid(values: &[f32], solid: &[bool]) -> f32 {
    let fluid: Vec<f64> = values
        .iter()
        .zip(solid)
        .filter(|(_, &solid)| !solid)
        .map(|(d, _)| (*d as f64).powi(2))
        .collect();
    (fluid.iter().sum::<f64>() / fluid.len().max(1) as f64).sqrt() as f32
}

/// The scene's wind run `steps` steps with each solver (its V-cycles, its
/// Jacobi iterations), multigrid first.
pub fn compare_solvers(gpu: &Gpu, scene: &Scene, steps: u32) -> Result<Vec<SolverTiming>> {
    let grid = scene.wind_grid()?;
    let commands = Commands::new(gpu, "wind solver comparison commands")?;
    let mut timings = Vec::new();
    for solver in [PressureSolver::Multigrid, PressureSolver::Jacobi] {
        let settings = WindSettings {
            solver,
            ..scene.wind.settings()
        };
        let run = run_steps(gpu, &commands, grid, &settings, steps, scene.wind.dt)?;
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
            rms_divergence_before: rms_over_fluid(&run.before, &run.field.solid),
            rms_divergence_after: run.field.rms_divergence(),
        });
    }
    Ok(timings)
}

fn run(
    gpu: &Gpu,
    scene: &Scene,
    grid: WindGrid,
    settings: &WindSettings,
    steps: u32,
    out_dir: &Path,
) -> Result<WindReport> {
    let dt = scene.wind.dt;
    let commands = Commands::new(gpu, "wind commands")?;
    let Stepped {
        field,
        times,
        before,
    } = run_steps(gpu, &commands, grid, settings, steps, dt)?;
    let max_divergence_before = before.iter().fold(0.0f32, |m, d| m.max(d.abs()));
    let rms_divergence_before = rms_over_fluid(&before, &field.solid);
    let max_speed = max_speed(&field);
    let tip_height = scene.grass.shape.height[1] * 0.8;
    let center = grid.origin + grid.size() / 2.0;
    for (name, slice) in [
        (
            "wind_horizontal.png",
            Slice::Horizontal { height: tip_height },
        ),
        ("wind_vertical.png", Slice::Vertical { depth: center.z }),
    ] {
        let (w, h, rgb) = wind_slices::render(&field, slice, max_speed);
        files::write_rgb_png(&out_dir.join(name), w, h, &rgb)?;
    }
    let timing = median_p95(&times);
    Ok(WindReport {
        scene: scene.name.clone(),
        device: gpu.info().name.clone(),
        cells: grid.cells.to_array(),
        solver: settings.solver,
        jacobi_iterations: settings.jacobi_iterations,
        v_cycles: settings.v_cycles,
        steps,
        dt,
        max_speed,
        max_divergence_before,
        max_divergence_after: field.max_divergence(),
        rms_divergence_before,
        rms_divergence_after: field.rms_divergence(),
        step_ms_median: timing.map(|t| t.0),
        step_ms_p95: timing.map(|t| t.1),
        solvers: compare_solvers(gpu, scene, steps)?,
        warnings: Vec::new(),
        validation: ValidationReport::default(),
    })
}

/// Largest speed at any cell centre.
fn max_speed(field: &WindField) -> f32 {
    field
        .grid
        .each_cell()
        .map(|(_, [i, j, k])| field.sample(field.grid.cell_center(i, j, k)).length())
        .fold(0.0, f32::max)
}
