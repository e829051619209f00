//! `meadow render`: its arguments, and what it prints of the
//! library's work (src/commands/render.rs).

use std::path::PathBuf;
use std::sync::atomic::Ordering;

use meadow::commands::render::{render_to_dir_observed, RenderRequest};

use meadow::scene::check::MAX_FRAMES;

use super::numbers;
use super::{signal_name, stop_signal, DeviceArgs, Interrupted, OverwriteArg, SceneArgs};

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Frames to render; frame f shows simulated time START + f / FPS.
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_FRAMES as u64))]
    frames: Option<u32>,
    /// Frames per second of simulated time (the simulation's own step
    /// is fixed by the scene).
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::decimal::<f32>)]
    fps: Option<f32>,
    /// Simulated seconds before the first frame (the grass starts at rest).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = numbers::decimal::<f32>)]
    start: Option<f32>,
    /// Write only every K-th frame (0, K, 2K, ...); the simulation still
    /// runs through the others.
    #[arg(long, value_name = "K", default_value_t = 1, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_FRAMES as u64))]
    every: u32,
    /// Do not write DIR/animation.gif (written when there are several frames).
    #[arg(long)]
    no_gif: bool,
    /// Also write the frames as a video by ffmpeg: FILE.mp4 (H.264) or
    /// FILE.webm (VP9), 4:2:0, near-lossless, at FPS / K frames a second.
    #[arg(long, value_name = "FILE")]
    video: Option<PathBuf>,
    /// Also measure the waves of light: how much each 16 x 16 pixel block
    /// of grass changes brightness over the frames, and how closely that
    /// follows its blades' displacement (report.json's light_waves; each
    /// frame is drawn once more, in a data view). Needs 3 frames or more.
    #[arg(long)]
    light_waves: bool,
    /// Folder for the frames, animation.gif, report.json and scene.toml
    /// (made if missing; an earlier render's outputs there are replaced).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let RenderArgs {
        scene: args,
        frames,
        fps,
        start,
        every,
        no_gif,
        video,
        light_waves,
        out,
        overwrite,
        device,
    } = args;
    let scene = args.load()?;
    let mut request = RenderRequest::from_scene(scene, device.options()?);
    let a = &mut request.animation;
    a.frames = frames.unwrap_or(a.frames);
    a.fps = fps.unwrap_or(a.fps);
    a.start = start.unwrap_or(a.start);
    request.width = args.width.unwrap_or(request.width);
    request.height = args.height.unwrap_or(request.height);
    request.msaa = args.msaa.unwrap_or(request.msaa);
    request.view = args.view.unwrap_or(request.view);
    request.every = every;
    request.gif = !no_gif;
    request.video = video;
    request.overwrite = overwrite.overwrite;
    // Asked on the command line, a render too short to measure is refused;
    // a scene's `light_waves = true` measures only when a series is
    // rendered (one frame of honami is a picture, not an error).
    request.light_waves = light_waves
        || (request.light_waves
            && request.frames_written().count() >= meadow::analysis::light_waves::LEAST_FRAMES);
    let (report, signal) = render_with_progress(&request, &out)?;
    for w in meadow::report::warnings::collapsed(&report.warnings) {
        eprintln!("meadow: warning: {w}");
    }
    print!("{}", meadow::report::render::summary(&report, &out));
    if report.interrupted {
        eprintln!(
            "meadow: interrupted after {} of {} frames; the files written are complete ({})",
            report.frames.len(),
            report.frames_planned,
            out.join("report.json").display()
        );
        let sig = signal.unwrap_or(signal_hook::consts::SIGINT);
        return Err(Interrupted(sig).into());
    }
    Ok(())
}

/// Renders with a progress bar on a terminal (none when stderr is not
/// one). SIGINT (Ctrl-C) and SIGTERM stop it between simulation steps or
/// frames: the files written so far stay complete and the report says how
/// far it got.
fn render_with_progress(
    request: &RenderRequest,
    out: &std::path::Path,
) -> anyhow::Result<(meadow::commands::render::RenderReport, Option<i32>)> {
    let signal = stop_signal()?;
    let planned = request.frames_written().count() as u64;
    let bar = indicatif::ProgressBar::new(planned);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} frames  {msg}  {elapsed} elapsed, {eta} left",
        )
        .expect("a valid progress template"),
    );
    let mut announced = false;
    let report = render_to_dir_observed(request, out, &mut |p| {
        bar.set_position(p.written as u64);
        bar.set_message(if p.steps_left > 0 {
            format!("simulating: {} steps to the next frame", p.steps_left)
        } else {
            String::new()
        });
        let sig = signal.load(Ordering::SeqCst) as i32;
        if sig != 0 && !announced {
            announced = true;
            bar.suspend(|| eprintln!("meadow: stopping ({})", signal_name(sig)));
        }
        sig == 0
    });
    bar.finish_and_clear();
    let sig = signal.load(Ordering::SeqCst) as i32;
    Ok((report?, (sig != 0).then_some(sig)))
}
