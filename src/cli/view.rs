//! `meadow view`: its arguments, and what it prints of the
//! library's work (src/commands/view.rs).

use std::path::PathBuf;

use meadow::commands::view::{read_script, ViewRequest};

use super::{signal_name, stop_signal, DeviceArgs, Interrupted, SceneArgs};

#[derive(clap::Args)]
pub struct ViewArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Timed input, one action per line ("1.5 key space"; see
    /// docs/viewer.md): a demo without a person.
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// Where P writes its screenshots.
    #[arg(long, default_value = "out/view")]
    out: PathBuf,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: ViewArgs) -> anyhow::Result<()> {
    let ViewArgs {
        scene: args,
        script,
        out,
        device,
    } = args;
    let scene = args.load()?;
    let script = script.as_deref().map(read_script).transpose()?;
    if let Some(note) = script.as_ref().and_then(|s| s.reordered.as_deref()) {
        eprintln!("meadow: warning: {note}");
    }
    let request = ViewRequest {
        width: args.width.unwrap_or(scene.render.width),
        height: args.height.unwrap_or(scene.render.height),
        msaa: args.msaa.unwrap_or(scene.render.msaa),
        view: args.view.unwrap_or(scene.render.view),
        script,
        screenshots: out,
        gpu: device.options()?,
        scene,
        stop: Some(stop_signal()?),
    };
    let report = meadow::commands::view::view(&request)?;
    println!(
        "showed {} frames in {:.1} s ({:.1} FPS; {:.1} s to start and stop), {:.2} s simulated; GPU memory {:.1} MiB (peak {:.1}); validation: {} errors",
        report.frames,
        report.wall_seconds,
        report.fps(),
        report.start_seconds,
        report.simulated_seconds,
        report.device_memory.allocated_bytes as f64 / (1 << 20) as f64,
        report.device_memory.peak_bytes as f64 / (1 << 20) as f64,
        report.validation.errors
    );
    if let Some(sig) = report.stopped_by {
        let sig = sig as i32;
        eprintln!(
            "meadow: interrupted by {}; the window closed cleanly",
            signal_name(sig)
        );
        return Err(Interrupted(sig).into());
    }
    Ok(())
}
