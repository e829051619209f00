//! `meadow reproduce`: its arguments, and what it prints of the
//! library's work (src/commands/reproduce.rs).

use std::path::PathBuf;

use super::{DeviceArgs, OverwriteArg};

#[derive(clap::Args)]
pub struct ReproduceArgs {
    /// Folder for index.md, index.html and each figure's shots (made if
    /// missing).
    #[arg(long, default_value = "out/reproduce")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    /// Small images and short simulated times: a few minutes on lavapipe.
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: ReproduceArgs) -> anyhow::Result<()> {
    let ReproduceArgs {
        out,
        overwrite,
        quick,
        device,
    } = args;
    let started = std::time::Instant::now();
    let rendered = meadow::commands::reproduce::reproduce(
        &out,
        quick,
        overwrite.overwrite,
        &device.options()?,
        &mut |p| {
            let left = p
                .seconds_left()
                .map_or(String::new(), |s| format!(", about {s:.0} s left"));
            eprintln!(
                "meadow: [{}/{}] {}: {} ({:.0} s so far{left})",
                p.done + 1,
                p.total,
                p.figure,
                p.shot,
                p.elapsed_s
            );
        },
    )?;
    let frames: usize = rendered.iter().map(|r| r.report.frames.len()).sum();
    println!(
        "reproduced {} shots ({frames} frames) in {:.0} s; wrote {} and {}",
        rendered.len(),
        started.elapsed().as_secs_f64(),
        out.join("index.md").display(),
        out.join("index.html").display()
    );
    Ok(())
}
