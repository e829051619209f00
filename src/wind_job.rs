//! `meadow wind` as a library call: the wind solver alone on the GPU, timed
//! per step with timestamp queries, with pictures of two slices and the
//! divergence before and after projection.

use std::path::Path;

use crate::error::Result;
use crate::gpu::commands::Commands;
use crate::gpu::timing::{median_p95, TimestampQueries};
use crate::gpu::{Gpu, GpuOptions, ValidationReport};
use crate::output;
use crate::render::wind_pass::WindPass;
use crate::render::wind_slices::{self, Slice};
use crate::scene::Scene;
use crate::sim::wind::{WindField, WindGrid, WindSettings};

/// Steps recorded into one submission (and timed with one query pool).
const STEPS_PER_SUBMIT: u32 = 100;

#[derive(Clone, Debug, serde::Serialize)]
pub struct WindReport {
    pub scene: String,
    pub device: String,
    pub cells: [u32; 3],
    pub jacobi_iterations: u32,
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
    output::ensure_dir(out_dir)?;
    let gpu = Gpu::new(gpu_options)?;
    let result = run(&gpu, scene, grid, &settings, steps, out_dir);
    let (mut report, validation) = gpu.finish(result)?;
    report.warnings = warnings;
    report.validation = validation;
    let json = serde_json::to_vec_pretty(&report).expect("report serialises");
    output::write_atomic(&out_dir.join("wind_report.json"), &json)?;
    report.validation.check()?;
    Ok(report)
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
    let pass = match WindPass::new(gpu, &commands, grid, settings) {
        Ok(p) => p,
        Err(e) => {
            commands.destroy(gpu);
            return Err(e);
        }
    };
    let timestamps = match TimestampQueries::new(gpu, STEPS_PER_SUBMIT, "wind step timestamps") {
        Ok(t) => t,
        Err(e) => {
            pass.destroy(gpu);
            commands.destroy(gpu);
            return Err(e);
        }
    };
    let result = (|| {
        let mut times = Vec::new();
        let mut done = 0;
        while done < steps {
            let batch = (steps - done).min(STEPS_PER_SUBMIT);
            let cmd = commands.begin(gpu)?;
            if let Some(t) = &timestamps {
                t.reset(gpu, cmd);
            }
            for n in 0..batch {
                if let Some(t) = &timestamps {
                    t.stamp(gpu, cmd, n, false);
                }
                pass.record_step(gpu, cmd, (done + n) as f32 * dt, dt);
                if let Some(t) = &timestamps {
                    t.stamp(gpu, cmd, n, true);
                }
            }
            commands.submit_and_wait(gpu, "wind steps")?;
            if let Some(t) = &timestamps {
                times.extend(t.read_ms(gpu, batch)?);
            }
            done += batch;
        }
        let mut field = WindField::new(grid, settings);
        field.vel = pass.read_velocity(gpu, &commands)?;
        let before = pass.read_divergence(gpu, &commands)?;
        let max_divergence_before = before.iter().fold(0.0f32, |m, d| m.max(d.abs()));
        let fluid: Vec<f64> = before
            .iter()
            .zip(&field.solid)
            .filter(|(_, &solid)| !solid)
            .map(|(d, _)| (*d as f64).powi(2))
            .collect();
        let rms_divergence_before =
            (fluid.iter().sum::<f64>() / fluid.len().max(1) as f64).sqrt() as f32;
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
            output::write_rgb_png(&out_dir.join(name), w, h, &rgb)?;
        }
        let timing = median_p95(&times);
        Ok(WindReport {
            scene: scene.name.clone(),
            device: gpu.info().name.clone(),
            cells: grid.cells.to_array(),
            jacobi_iterations: settings.jacobi_iterations,
            steps,
            dt,
            max_speed,
            max_divergence_before,
            max_divergence_after: field.max_divergence(),
            rms_divergence_before,
            rms_divergence_after: field.rms_divergence(),
            step_ms_median: timing.map(|t| t.0),
            step_ms_p95: timing.map(|t| t.1),
            warnings: Vec::new(),
            validation: ValidationReport::default(),
        })
    })();
    if let Some(t) = timestamps {
        t.destroy(gpu);
    }
    pass.destroy(gpu);
    commands.destroy(gpu);
    result
}

/// Largest speed at any cell centre.
fn max_speed(field: &WindField) -> f32 {
    field
        .grid
        .each_cell()
        .map(|(_, [i, j, k])| field.sample(field.grid.cell_center(i, j, k)).length())
        .fold(0.0, f32::max)
}
