//! `meadow gpu-report`: its arguments, and what it prints of the library's
//! work (src/commands/gpu_report/).

use std::path::PathBuf;

use super::{DeviceArgs, OverwriteArg};

#[derive(clap::Args)]
pub struct GpuReportArgs {
    /// The reduced set: small sizes lavapipe runs in minutes, to check the
    /// report works (its figures are not the targets').
    #[arg(long)]
    quick: bool,
    /// Folder for <device>.json and <device>.md (made if missing).
    #[arg(long, default_value = "docs/bench")]
    out: PathBuf,
    /// Folder for the commands' own outputs (bench.md, wind slices,
    /// frames), one folder per part.
    #[arg(long, default_value = "out/gpu-report")]
    work: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: GpuReportArgs) -> anyhow::Result<()> {
    let GpuReportArgs {
        quick,
        out,
        work,
        overwrite,
        device,
    } = args;
    let gpu = device.options()?;
    if gpu.validation.enabled {
        anyhow::bail!(
            "--validation would slow every timed run; gpu-report runs each command once more under validation by itself, drop the flag"
        );
    }
    let request = meadow::commands::gpu_report::GpuReportRequest {
        quick,
        work,
        overwrite: overwrite.overwrite,
        gpu,
    };
    let started = std::time::Instant::now();
    let (report, md) =
        meadow::commands::gpu_report::gpu_report(&request, &out, &mut |part: &str| {
            eprintln!(
                "gpu-report [{:>4.0} s] {part}",
                started.elapsed().as_secs_f64()
            );
        })?;
    println!(
        "{} ({}), driver {}, Vulkan {}, commit {}",
        report.device, report.device_type, report.driver, report.api_version, report.commit
    );
    for t in &report.targets {
        let verdict = match t.met {
            Some(true) => "met",
            Some(false) => "MISSED",
            None => "not measured",
        };
        let figure = t
            .measured
            .map_or(String::new(), |v| format!(": {v:.3} {}", t.unit));
        println!("target {}{figure} ({verdict}; {})", t.name, t.note);
    }
    println!(
        "wrote {} and {}",
        md.display(),
        md.with_extension("json").display()
    );
    let failures = report.failures();
    if !failures.is_empty() {
        for f in &failures {
            eprintln!("gpu-report: failed: {f}");
        }
        anyhow::bail!(
            "{} part(s) failed ({} says why each), the first: {}",
            failures.len(),
            md.display(),
            failures[0]
        );
    }
    Ok(())
}
