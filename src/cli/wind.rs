//! `meadow wind`: its arguments, and what it prints of the
//! library's work (src/commands/wind.rs).

use std::path::PathBuf;

use meadow::commands::wind::WindReport;
use meadow::model::wind::{Advection, Coupling};
use meadow::scene::Scene;

use meadow::scene::check::MAX_V_CYCLES;

use super::{numbers, DeviceArgs, OverwriteArg};

/// The most steps `wind` runs.
const MAX_STEPS: u64 = 1_000_000;

#[derive(clap::Args)]
pub struct WindArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "fig10-few-bunches")]
    scene: String,
    /// Simulation steps to run.
    #[arg(long, default_value_t = 120, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_STEPS))]
    steps: u32,
    /// Solve the pressure by N Jacobi iterations, the paper's solver
    /// (default: the scene's solver and count).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, 10_000))]
    jacobi_iterations: Option<u32>,
    /// Solve the pressure by multigrid, at most N V-cycles a step (default 7;
    /// each step stops at wind.pressure_tolerance, most after two).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_V_CYCLES as u64))]
    v_cycles: Option<u32>,
    /// Wind grid cells X,Y,Z, y up (default: the scene's, e.g. 60,20,60).
    #[arg(long, value_name = "X,Y,Z")]
    cells: Option<String>,
    /// Whether the grass slows the wind: one-way (the paper's) or
    /// two-way (canopy drag; default: the scene's wind.coupling).
    #[arg(long, value_enum)]
    coupling: Option<Coupling>,
    /// How the wind carries itself: maccormack (second order, bounded) or
    /// semi-lagrangian (the paper's; default: the scene's wind.advection).
    #[arg(long, value_enum)]
    advection: Option<Advection>,
    /// Folder for wind_horizontal.svg, wind_vertical.svg, wind_field.npy
    /// and wind_report.json (made if missing).
    #[arg(long, default_value = "out/wind")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: WindArgs) -> anyhow::Result<()> {
    let WindArgs {
        scene,
        steps,
        jacobi_iterations,
        v_cycles,
        cells,
        coupling,
        advection,
        out,
        overwrite,
        device,
    } = args;
    let scene = scene_asked(
        &scene,
        coupling,
        advection,
        (jacobi_iterations, v_cycles),
        cells,
    )?;
    // The steps on a terminal as they run: a default run takes about a
    // minute on lavapipe.
    let bar = indicatif::ProgressBar::new(meadow::commands::wind::steps_run(&scene, steps));
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} wind steps (the scene's, then each solver's and advection's)  {elapsed} elapsed, {eta} left",
        )
        .expect("a valid progress template"),
    );
    let r = meadow::commands::wind::wind_to_dir(
        &scene,
        steps,
        &device.options()?,
        &out,
        overwrite.overwrite,
        &mut |batch| bar.inc(batch as u64),
    );
    bar.finish_and_clear();
    let r = r?;
    for w in meadow::report::warnings::collapsed(&r.warnings) {
        eprintln!("meadow: warning: {w}");
    }
    print_report(&r);
    println!(
        "wrote {}, {} and {}",
        out.join("wind_horizontal.svg").display(),
        out.join("wind_vertical.svg").display(),
        out.join("wind_field.npy").display()
    );
    Ok(())
}

/// The scene as the command line changes it.
fn scene_asked(
    name: &str,
    coupling: Option<Coupling>,
    advection: Option<Advection>,
    (jacobi_iterations, v_cycles): (Option<u32>, Option<u32>),
    cells: Option<String>,
) -> anyhow::Result<Scene> {
    let mut scene = Scene::load(name)?;
    if let Some(c) = coupling {
        scene.wind.coupling = c;
    }
    if let Some(a) = advection {
        scene.wind.advection = a;
    }
    if jacobi_iterations.is_some() && v_cycles.is_some() {
        anyhow::bail!(
            "--jacobi-iterations and --v-cycles pick different pressure solvers; give one"
        );
    }
    if let Some(n) = jacobi_iterations {
        scene.set_jacobi_iterations(n)?;
    }
    if let Some(n) = v_cycles {
        scene.set_v_cycles(n)?;
    }
    if let Some(cells) = cells {
        scene.set_wind_cells(&cells)?;
    }
    Ok(scene)
}

/// What the run measured, on the terminal.
fn print_report(r: &WindReport) {
    let solve = meadow::report::wind::describe(r.solver, r.jacobi_iterations, r.v_cycles);
    println!(
        "wind {} on {}: grid {}x{}x{}, {solve}, {} steps of {:.4} s",
        r.scene, r.device, r.cells[0], r.cells[1], r.cells[2], r.steps, r.dt
    );
    if let (Some(median), Some(most)) = (r.v_cycles_median, r.v_cycles_most) {
        println!(
            "V-cycles per step: median {median}, most {most} (stopping at {:.0e} of the divergence left)",
            r.pressure_tolerance
        );
    }
    let sweeps = r
        .sweep
        .map(|s| format!(" ({} sweeps)", s.name()))
        .unwrap_or_default();
    println!(
        "dispatches per step: {} ran workgroups, {} recorded{sweeps}",
        r.dispatches_per_step, r.dispatches_recorded
    );
    println!("max speed {:.3} m/s", r.max_speed);
    println!(
        "max |divergence| before projection {:.4e} 1/s, after {:.4e} 1/s",
        r.max_divergence_before, r.max_divergence_after
    );
    println!(
        "rms |divergence| before projection {:.4e} 1/s, after {:.4e} 1/s",
        r.rms_divergence_before, r.rms_divergence_after
    );
    match (r.step_ms_median, r.step_ms_p95) {
        (Some(m), Some(p)) => println!(
            "GPU time per step (timestamps): median {m:.3} ms, p95 {p:.3} ms over {} steps",
            r.steps
        ),
        _ => println!("GPU time per step: unavailable (the device has no timestamps)"),
    }
    println!("both solvers over the same {} steps:", r.steps);
    for t in &r.solvers {
        let ms = t
            .step_ms_median
            .map_or("unavailable".to_string(), |m| format!("{m:.3} ms"));
        println!(
            "  {:<9} x{:<3} median {ms} per step, leaves {:.2}% of the divergence",
            t.solver.name(),
            t.iterations,
            100.0 * t.share_left()
        );
    }
    if let Some(t) = &r.turbulence_cost {
        match (t.step_ms_median_with, t.step_ms_median_without, t.ratio) {
            (Some(with), Some(without), Some(ratio)) => println!(
                "the step with turbulence and without over the same {} steps: median {with:.3} ms against {without:.3} ms ({ratio:.2}x)",
                t.steps
            ),
            _ => println!("the step with turbulence and without: unavailable (no timestamps)"),
        }
    }
    let a = &r.advection_cost;
    match (a.step_ms_median_maccormack, a.step_ms_median_semi_lagrangian, a.ratio) {
        (Some(mac), Some(semi), Some(ratio)) => println!(
            "the step with MacCormack's advection and the paper's semi-Lagrangian over the same {} steps: median {mac:.3} ms against {semi:.3} ms ({ratio:.2}x; this scene's: {})",
            a.steps,
            r.advection.name()
        ),
        _ => println!("the step with each advection: unavailable (no timestamps)"),
    }
}
