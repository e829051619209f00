//! `meadow trace`: its arguments, and what it prints of the
//! library's work (src/commands/trace.rs).

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use meadow::model::wind::Coupling;
use meadow::scene::Scene;

use meadow::commands::trace::{TraceReport, MAX_EVERY};

use super::numbers;
use super::{stop_signal, DeviceArgs, Interrupted, OverwriteArg};

#[derive(clap::Args)]
pub struct TraceArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "table1")]
    scene: String,
    /// Simulated seconds.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true, value_parser = numbers::seconds)]
    seconds: f64,
    /// A sample every N simulation steps (the scene's dt each).
    #[arg(long, value_name = "N", default_value_t = 1, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_EVERY as u64))]
    every: u32,
    /// How many blades to trace, picked evenly through the field by the
    /// seed, or "all".
    #[arg(long, value_name = "K|all", default_value = "100")]
    blades: String,
    /// Also write the wind at each traced tip (wind_x, wind_y, wind_z).
    #[arg(long)]
    wind: bool,
    /// DIR/space_time.svg, plan_view.svg's statistics and the spectrum
    /// start at this simulated time (leave out the grass leaning into a
    /// wind that is still filling the field).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, allow_negative_numbers = true, value_parser = numbers::seconds)]
    diagram_from: f64,
    /// Random seed of the grass field (default: the scene's).
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::seed)]
    seed: Option<u64>,
    /// Whether the grass slows the wind: one-way (the paper's) or
    /// two-way (canopy drag; default: the scene's wind.coupling).
    #[arg(long, value_enum)]
    coupling: Option<Coupling>,
    /// Folder for blades.csv, trace.json, space_time.svg, plan_view.svg
    /// and spectrum.svg (made if missing).
    #[arg(long, default_value = "out/trace")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: TraceArgs) -> anyhow::Result<()> {
    let TraceArgs {
        scene,
        seconds,
        every,
        blades,
        wind,
        diagram_from,
        seed,
        coupling,
        out,
        overwrite,
        device,
    } = args;
    use meadow::commands::trace::{trace_to_dir, BladePick, TraceRequest};
    let mut scene = Scene::load(&scene)?;
    if let Some(c) = coupling {
        scene.wind.coupling = c;
    }
    if let Some(s) = seed {
        scene.seed = s;
    }
    let request = TraceRequest {
        scene,
        seconds,
        every,
        blades: BladePick::parse(&blades)?,
        wind,
        diagram_from,
        gpu: device.options()?,
    };
    let signal = stop_signal()?;
    let bar = indicatif::ProgressBar::new(request.steps());
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} steps  {elapsed} elapsed, {eta} left",
        )
        .expect("a valid progress template"),
    );
    let report = trace_to_dir(&request, &out, overwrite.overwrite, &mut |done, _| {
        bar.set_position(done);
        signal.load(Ordering::SeqCst) == 0
    });
    bar.finish_and_clear();
    let report = report?;
    print_report(&report, &out);
    let sig = signal.load(Ordering::SeqCst) as i32;
    if report.interrupted {
        eprintln!(
            "meadow: interrupted after {} of {} samples' time; the files written are complete",
            report.samples,
            report.steps_planned / report.every as u64 + 1
        );
        return Err(Interrupted(if sig != 0 {
            sig
        } else {
            signal_hook::consts::SIGINT
        })
        .into());
    }
    Ok(())
}

/// What the trace measured and wrote, on the terminal.
fn print_report(report: &TraceReport, out: &Path) {
    println!(
        "trace {} on {}: {} of {} blades, {} samples every {} steps of {:.4} s",
        report.scene,
        report.device,
        report.blades_traced,
        report.blades_total,
        report.samples,
        report.every,
        report.dt
    );
    if let (Some(spectrum), Some(bend)) = (&report.tip_spectrum, &report.bend_natural_hz) {
        let swing = report.swing_natural_hz.map_or(String::new(), |s| {
            format!(", swinging {:.2} Hz ({:.2}-{:.2})", s.median, s.p5, s.p95)
        });
        println!(
            "tip motion (x) from {:.1} s peaks at {:.2} Hz; the traced blades' natural frequencies: bending {:.2} Hz (5-95%: {:.2}-{:.2}){swing}; the spectrum is in trace.json and spectrum.svg",
            spectrum.from_s, spectrum.peak_hz, bend.median, bend.p5, bend.p95
        );
    }
    if let Some(s) = &report.tip_spectrum_scaled {
        println!(
            "tip motion per unit log frequency, each blade against its own bending frequency: largest at {:.2} f_bend{} ({} blades)",
            s.peak_over_natural,
            if s.peak_is_slowest_band { ", the slowest band: no peak" } else { "" },
            s.blades
        );
    }
    if let Some(c) = &report.tip_correlation {
        println!(
            "tips' correlation ({:.1} m cells): integral length {:.1} m along the wind, {:.1} m across{}",
            c.cell_m,
            c.along_length_m,
            c.across_length_m,
            c.bands_20m_across
                .map_or(String::new(), |r| format!("; bands 20 m apart across it correlate {r:.2}"))
        );
    }
    let mut written = vec![
        out.join(&report.csv),
        out.join(meadow::commands::trace::REPORT_NAME),
    ];
    for picture in [&report.space_time, &report.plan_view, &report.spectrum]
        .into_iter()
        .flatten()
    {
        written.push(out.join(picture));
    }
    let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    println!("wrote {}", written.join(", "));
}
