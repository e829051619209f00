//! The `meadow` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use std::sync::atomic::Ordering;

use anyhow::Context as _;

use clap::{Parser, Subcommand, ValueEnum};

use meadow::commands::render::{render_to_dir_observed, RenderRequest};
use meadow::commands::view::{read_script, ViewRequest};
use meadow::gpu::{FaultPlan, GpuOptions, ValidationOptions};
use meadow::scene::{Scene, ViewMode};
use meadow::sim::wind::Coupling;

#[derive(Parser)]
#[command(
    name = "meadow",
    version,
    about = "Grass swaying in dynamic wind (Lee et al. 2016) on Vulkan"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum LodArg {
    Both,
    On,
    Off,
}

#[derive(clap::Args)]
struct DeviceArgs {
    /// Use the first Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Enable the Khronos validation layer (core and synchronization checks);
    /// any error it reports makes the run fail.
    #[arg(long)]
    validation: bool,
    /// With --validation: also the best-practices checks (warnings).
    #[arg(long, requires = "validation")]
    best_practices: bool,
    /// Refuse work that needs more GPU memory than this (default: half the
    /// device's largest memory heap).
    #[arg(long, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..=16_777_216))]
    gpu_memory_mib: Option<u64>,
}

impl DeviceArgs {
    fn options(&self) -> anyhow::Result<GpuOptions> {
        Ok(GpuOptions {
            validation: ValidationOptions {
                enabled: self.validation,
                synchronization: self.validation,
                best_practices: self.best_practices,
            },
            device_name: self.device.clone(),
            // A test hook: pretend the device lacks these features.
            pretend_missing: std::env::var("MEADOW_PRETEND_MISSING")
                .map(|v| {
                    v.split(',')
                        .filter(|s| !s.is_empty())
                        .map(String::from)
                        .collect()
                })
                .unwrap_or_default(),
            memory_budget: self.gpu_memory_mib.map(|m| m << 20),
            storage_range: None,
            window_extensions: Vec::new(),
            // A test hook: fail the N-th allocation or submission.
            faults: FaultPlan::parse(&std::env::var("MEADOW_INJECT_FAULT").unwrap_or_default())?,
        })
    }
}

#[derive(Subcommand)]
enum Command {
    /// Simulate and render a scene offscreen: DIR/frame_0000.png ... and
    /// DIR/report.json.
    Render {
        #[command(flatten)]
        scene: SceneArgs,
        /// Frames to render; frame f shows simulated time START + f / FPS.
        #[arg(long)]
        frames: Option<u32>,
        /// Frames per second of simulated time (the simulation's own step
        /// is fixed by the scene).
        #[arg(long, allow_negative_numbers = true)]
        fps: Option<f32>,
        /// Simulated seconds before the first frame (the grass starts at rest).
        #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
        start: Option<f32>,
        /// Write only every K-th frame (0, K, 2K, ...); the simulation still
        /// runs through the others.
        #[arg(long, value_name = "K", default_value_t = 1)]
        every: u32,
        /// Do not write DIR/animation.gif (written when there are several frames).
        #[arg(long)]
        no_gif: bool,
        /// Also write the frames as a video by ffmpeg: FILE.mp4 (H.264) or
        /// FILE.webm (VP9), 4:2:0, near-lossless, at FPS / K frames a second.
        #[arg(long, value_name = "FILE")]
        video: Option<PathBuf>,
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// The meadow live in a window: both phases every frame, simulated
    /// time following the clock. Keys: W A S D Q E fly, drag to look,
    /// wheel speed; space pause, . step, [ ] time slower/faster, L LOD,
    /// V views, P screenshot (DIR/view_NNNN.png), arrows steer the wind,
    /// click drops a gust, B a ball (right click rolls it there), O
    /// overlay, H keys, Esc quit.
    View {
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
    },
    /// Run the wind solver (with two-way coupling, the grass too); write
    /// two slices of the field as SVG (wind_horizontal.svg,
    /// wind_vertical.svg) and wind_report.json, print speeds, divergence
    /// and GPU time per step.
    Wind {
        /// A built-in scene or a scene file (.toml).
        #[arg(long, default_value = "fig10-few-bunches")]
        scene: String,
        /// Simulation steps to run.
        #[arg(long, default_value_t = 120)]
        steps: u32,
        /// Solve the pressure by N Jacobi iterations, the paper's solver
        /// (default: the scene's solver and count).
        #[arg(long, value_name = "N")]
        jacobi_iterations: Option<u32>,
        /// Solve the pressure by N multigrid V-cycles (the default 7 leave under 1% of
        /// the divergence on the shipped scenes).
        #[arg(long, value_name = "N")]
        v_cycles: Option<u32>,
        /// Wind grid cells X,Y,Z, y up (default: the scene's, e.g. 60,20,60).
        #[arg(long, value_name = "X,Y,Z")]
        cells: Option<String>,
        /// Whether the grass slows the wind: one-way (the paper's) or
        /// two-way (canopy drag; default: the scene's wind.coupling).
        #[arg(long, value_enum)]
        coupling: Option<Coupling>,
        #[arg(long, default_value = "out/wind")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// The paper's Table 1 on this device: the table1 scene at each blade
    /// count, with and without LOD, every frame phase timed on the GPU, plus
    /// the vertex+fragment floor; writes DIR/bench.json, bench.md, bench.svg.
    Bench {
        /// A built-in scene or a scene file (.toml).
        #[arg(long, default_value = "table1")]
        scene: String,
        /// Blade counts, comma-separated (50k, 1.5m, 1200); counts past 200K
        /// run when asked, after a check that they fit the GPU's memory.
        #[arg(long, default_value = "50k,100k,150k,200k")]
        blades: String,
        #[arg(long, value_enum, default_value = "both")]
        lod: LodArg,
        /// Timed frames per row (each one simulation step).
        #[arg(long, default_value_t = 20)]
        frames: u32,
        /// Untimed frames before them.
        #[arg(long, default_value_t = 3)]
        warmup: u32,
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
        /// MSAA samples asked for (the paper's 8; the largest supported up
        /// to this is used and reported).
        #[arg(long, default_value_t = 8)]
        msaa: u32,
        /// Shadow map side in texels (default: the scene's, the paper's 8192;
        /// 0 turns shadows off).
        #[arg(long, value_name = "TEXELS")]
        shadow_map: Option<u32>,
        /// Occlusion culling in the rows with culling on (default: the
        /// scene's [cull] occlusion, off).
        #[arg(long, value_enum)]
        occlusion: Option<OnOff>,
        #[arg(long, default_value = "out/bench")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// Time the grass step alone on the GPU (timestamp queries) at several
    /// blade counts, beside the paper's figures; writes DIR/grass_bench.json.
    BenchGrass {
        /// A built-in scene or a scene file (.toml).
        #[arg(long, default_value = "table1")]
        scene: String,
        /// Blade counts, comma-separated (50k, 1.5m, 1200).
        #[arg(long, default_value = "50k,100k,150k,200k")]
        blades: String,
        /// Numbers of balls rolling through the field, comma-separated
        /// (e.g. 0,1,16,128): each blade count runs with each, and each
        /// row gives its cost over the count's row without (0).
        #[arg(long, default_value = "0")]
        colliders: String,
        /// Timed steps per count (the median and p95 are reported).
        #[arg(long, default_value_t = 30)]
        steps: u32,
        /// Untimed grass steps before timing.
        #[arg(long, default_value_t = 5)]
        warmup: u32,
        #[arg(long, default_value = "out/bench-grass")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// Render every figure scene of the paper (Fig. 10-13) and write
    /// DIR/index.md and a self-contained DIR/index.html beside the paper's
    /// descriptions and the parameters used.
    Reproduce {
        #[arg(long, default_value = "out/reproduce")]
        out: PathBuf,
        /// Small images and short simulated times: a few minutes on lavapipe.
        #[arg(long)]
        quick: bool,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// Simulate a scene (no rendering) and write the grass's motion as
    /// data: DIR/blades.csv (time_s, blade, root, tip, swing, bend, twist
    /// per traced blade per sample), DIR/trace.json (columns, units, scene,
    /// seed, device, dt) and DIR/space_time.svg (the motion along x over
    /// time: travelling gusts are diagonal stripes).
    Trace {
        /// A built-in scene or a scene file (.toml).
        #[arg(long, default_value = "table1")]
        scene: String,
        /// Simulated seconds.
        #[arg(long, default_value_t = 10.0)]
        seconds: f64,
        /// A sample every N simulation steps (the scene's dt each).
        #[arg(long, value_name = "N", default_value_t = 1)]
        every: u32,
        /// How many blades to trace, picked evenly through the field by the
        /// seed, or "all".
        #[arg(long, value_name = "K|all", default_value = "100")]
        blades: String,
        /// Also write the wind at each traced tip (wind_x, wind_y, wind_z).
        #[arg(long)]
        wind: bool,
        /// DIR/space_time.svg starts at this simulated time (leave out the
        /// grass leaning into a wind that is still filling the field).
        #[arg(long, value_name = "SECONDS", default_value_t = 0.0)]
        diagram_from: f64,
        /// Random seed of the grass field (default: the scene's).
        #[arg(long)]
        seed: Option<u64>,
        /// Whether the grass slows the wind: one-way (the paper's) or
        /// two-way (canopy drag; default: the scene's wind.coupling).
        #[arg(long, value_enum)]
        coupling: Option<Coupling>,
        #[arg(long, default_value = "out/trace")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// List the Vulkan devices and whether each can run meadow.
    Devices {
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// List the built-in scenes; with --print NAME, write one as TOML to
    /// stdout (a start for a scene of one's own).
    Scenes {
        #[arg(long, value_name = "NAME")]
        print: Option<String>,
    },
}

/// A render stopped by a signal: the process exits 128 + its number (130
/// for SIGINT, 143 for SIGTERM), as a shell reports a process killed by it.
#[derive(Debug)]
struct Interrupted(i32);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted by {}", signal_name(self.0))
    }
}

impl std::error::Error for Interrupted {}

fn signal_name(signal: i32) -> &'static str {
    match signal {
        signal_hook::consts::SIGINT => "SIGINT (Ctrl-C)",
        signal_hook::consts::SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}

/// SIGINT and SIGTERM stored as their number when they arrive (0 until
/// then): the handlers only store it (async-signal-safe); the long
/// commands poll it between steps and stop cleanly.
fn stop_signal() -> anyhow::Result<std::sync::Arc<std::sync::atomic::AtomicUsize>> {
    let signal = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_usize(sig, signal.clone(), sig as usize)
            .context("installing the SIGINT/SIGTERM handlers")?;
    }
    Ok(signal)
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

/// The scene and what `render` and `view` may change of it from the
/// command line.
#[derive(clap::Args)]
struct SceneArgs {
    /// A built-in scene (`meadow scenes` lists them) or a scene file (.toml).
    #[arg(long, default_value = "table1")]
    scene: String,
    /// Total number of blades, shared among the scene's patches (200000,
    /// 200k, 1.5m).
    #[arg(long)]
    blades: Option<String>,
    /// Width in pixels of the image (render) or of the window at the start
    /// (view); default: the scene's [render] width.
    #[arg(long)]
    width: Option<u32>,
    /// Height in pixels, as --width (default: the scene's [render] height).
    #[arg(long)]
    height: Option<u32>,
    /// MSAA samples asked for; the largest supported count up to it is used.
    #[arg(long)]
    msaa: Option<u32>,
    /// Level of detail: tessellation level 20/10/3 by distance, or always 20.
    #[arg(long, value_enum)]
    lod: Option<OnOff>,
    /// Culling: draw only the blades the view (and its shadows) can
    /// show, listed by a compute pass each frame; off draws every blade
    /// in both passes (default: the scene's [cull], on).
    #[arg(long, value_enum)]
    cull: Option<OnOff>,
    /// Occlusion culling (with --cull on): leave out the blades hidden
    /// behind the previous frame's depth (default: the scene's [cull]
    /// occlusion, off: it pays only behind large occluders).
    #[arg(long, value_enum)]
    occlusion: Option<OnOff>,
    /// What to show: the shaded grass, or a debug view.
    #[arg(long, value_enum)]
    view: Option<ViewMode>,
    /// Random seed of the grass field (default: the scene's).
    #[arg(long)]
    seed: Option<u64>,
    /// Whether the grass slows the wind: one-way (the paper's) or
    /// two-way (canopy drag; default: the scene's wind.coupling).
    #[arg(long, value_enum)]
    coupling: Option<Coupling>,
    /// Shadow map side in texels (default: the scene's, the paper's 8192;
    /// smaller for quick previews; 0 turns shadows off).
    #[arg(long, value_name = "TEXELS")]
    shadow_map: Option<u32>,
}

impl SceneArgs {
    /// The scene loaded, with the overrides applied (size, MSAA and view
    /// are the caller's: they go to the request, not the scene).
    fn load(&self) -> anyhow::Result<Scene> {
        let mut scene = Scene::load(&self.scene)?;
        if let Some(c) = self.coupling {
            scene.wind.coupling = c;
        }
        if let Some(n) = self.shadow_map {
            scene.set_shadow_map(n)?;
        }
        if let Some(text) = &self.blades {
            scene.set_blade_count(blade_count(text)?)?;
        }
        if let Some(s) = self.seed {
            scene.seed = s;
        }
        if let Some(lod) = self.lod {
            scene.lod.enabled = lod == OnOff::On;
        }
        if let Some(cull) = self.cull {
            scene.cull.enabled = cull == OnOff::On;
        }
        if let Some(occlusion) = self.occlusion {
            if occlusion == OnOff::On && !scene.cull.enabled {
                anyhow::bail!(
                    "--occlusion on is part of culling, which is off; drop --cull off (or the scene's [cull] enabled = false)"
                );
            }
            scene.cull.occlusion = occlusion == OnOff::On;
        }
        Ok(scene)
    }
}

/// `--blades` as every command reads it: 1200, 50k, 1.5m. A plain
/// number is passed on as it is, for the scene to refuse by range.
fn blade_count(text: &str) -> anyhow::Result<usize> {
    match text.trim().parse::<usize>() {
        Ok(n) => Ok(n),
        Err(_) => Ok(meadow::commands::bench_grass::parse_count(text)?),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<Interrupted>() => {
            let Interrupted(sig) = e.downcast_ref::<Interrupted>().expect("checked");
            ExitCode::from((128 + sig).clamp(0, 255) as u8)
        }
        Err(e) => {
            // One line: the cause chain, outermost first, without repeating
            // a cause its parent's message already ends with.
            let mut msg: Vec<String> = Vec::new();
            for cause in e.chain() {
                let text = cause.to_string();
                if !msg.last().is_some_and(|last| last.ends_with(&text)) {
                    msg.push(text);
                }
            }
            eprintln!("meadow: error: {}", msg.join(": "));
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render {
            scene: args,
            frames,
            fps,
            start,
            every,
            no_gif,
            video,
            out,
            device,
        } => {
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
            let (report, signal) = render_with_progress(&request, &out)?;
            for w in &report.warnings {
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
        Command::View {
            scene: args,
            script,
            out,
            device,
        } => {
            let scene = args.load()?;
            let request = ViewRequest {
                width: args.width.unwrap_or(scene.render.width),
                height: args.height.unwrap_or(scene.render.height),
                msaa: args.msaa.unwrap_or(scene.render.msaa),
                view: args.view.unwrap_or(scene.render.view),
                script: script.as_deref().map(read_script).transpose()?,
                screenshots: out,
                gpu: device.options()?,
                scene,
                stop: Some(stop_signal()?),
            };
            let report = meadow::commands::view::view(&request)?;
            println!(
                "showed {} frames in {:.1} s ({:.1} FPS; {:.1} s to start and stop), {:.2} s simulated; validation: {} errors",
                report.frames,
                report.wall_seconds,
                report.fps(),
                report.start_seconds,
                report.simulated_seconds,
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
        Command::Wind {
            scene,
            steps,
            jacobi_iterations,
            v_cycles,
            cells,
            coupling,
            out,
            device,
        } => {
            if steps == 0 || steps > 1_000_000 {
                anyhow::bail!("--steps {steps} is not allowed, use 1..=1000000");
            }
            let mut scene = Scene::load(&scene)?;
            if let Some(c) = coupling {
                scene.wind.coupling = c;
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
            let r = meadow::commands::wind::wind_to_dir(&scene, steps, &device.options()?, &out)?;
            for w in &r.warnings {
                eprintln!("meadow: warning: {w}");
            }
            let solve = meadow::report::wind::describe(r.solver, r.jacobi_iterations, r.v_cycles);
            println!(
                "wind {} on {}: grid {}x{}x{}, {solve}, {} steps of {:.4} s",
                r.scene, r.device, r.cells[0], r.cells[1], r.cells[2], r.steps, r.dt
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
            println!(
                "wrote {} and {}",
                out.join("wind_horizontal.svg").display(),
                out.join("wind_vertical.svg").display()
            );
            Ok(())
        }
        Command::Bench {
            scene,
            blades,
            lod,
            frames,
            warmup,
            width,
            height,
            msaa,
            shadow_map,
            occlusion,
            out,
            device,
        } => {
            let counts = blades
                .split(',')
                .map(meadow::commands::bench_grass::parse_count)
                .collect::<Result<Vec<_>, _>>()?;
            let mut scene = Scene::load(&scene)?;
            if let Some(n) = shadow_map {
                scene.set_shadow_map(n)?;
            }
            if let Some(occlusion) = occlusion {
                scene.cull.occlusion = occlusion == OnOff::On;
            }
            let request = meadow::commands::bench::BenchRequest {
                scene,
                counts,
                lod: match lod {
                    LodArg::Both => meadow::commands::bench::LodChoice::Both,
                    LodArg::On => meadow::commands::bench::LodChoice::On,
                    LodArg::Off => meadow::commands::bench::LodChoice::Off,
                },
                frames,
                warmup,
                width,
                height,
                msaa,
                gpu: device.options()?,
            };
            let bench = meadow::commands::bench::bench_to_dir(&request, &out)?;
            print!("{}", meadow::commands::bench::markdown(&bench));
            println!(
                "wrote {}, bench.md and bench.svg",
                out.join("bench.json").display()
            );
            Ok(())
        }
        Command::BenchGrass {
            scene,
            blades,
            colliders,
            steps,
            warmup,
            out,
            device,
        } => {
            let scene = Scene::load(&scene)?;
            let counts = blades
                .split(',')
                .map(meadow::commands::bench_grass::parse_count)
                .collect::<Result<Vec<_>, _>>()?;
            let colliders = colliders
                .split(',')
                .map(|c| {
                    c.trim().parse::<usize>().map_err(|_| {
                        anyhow::anyhow!(
                            "collider count {c:?} is not a count, write e.g. --colliders 0,1,16,128"
                        )
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            meadow::report::files::ensure_dir(&out)?;
            let bench = meadow::commands::bench_grass::bench_grass(
                &scene,
                &counts,
                &colliders,
                steps,
                warmup,
                &device.options()?,
            )?;
            let json = serde_json::to_vec_pretty(&bench).expect("bench serialises");
            let path = out.join("grass_bench.json");
            meadow::report::files::write_atomic(&path, &json)?;
            println!(
                "grass step on {} [{}], scene {}, {} timed steps per count (medians)",
                bench.device, bench.device_type, bench.scene, steps
            );
            match &bench.copy_bandwidth {
                Some(c) => println!(
                    "memory floor: the bytes each step must read and write at {:.1} GB/s, this device's \
                     copy bandwidth (median of {} copies of {} MiB, read + write)",
                    c.gb_per_s,
                    c.copies,
                    c.bytes >> 20
                ),
                None => println!("memory floor: n/a (no timestamps on this device)"),
            }
            println!(
                "{:>9}  {:>9}  {:>8}  {:>10}  {:>10}  {:>18}  {:>10}  {:>9}  {:>11}  {:>10}  {:>8}",
                "blades",
                "colliders",
                "substeps",
                "median ms",
                "p95 ms",
                "paper (GTX 670) ms",
                "MB / step",
                "floor ms",
                "step/floor",
                "x no coll.",
                "touching"
            );
            let ms = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.3}"));
            for r in &bench.rows {
                println!(
                    "{:>9}  {:>9}  {:>8}  {:>10}  {:>10}  {:>18}  {:>10.1}  {:>9}  {:>11}  {:>10}  {:>7.1}%",
                    r.blades,
                    r.colliders,
                    r.substeps,
                    ms(r.step_ms_median),
                    ms(r.step_ms_p95),
                    r.paper_ms.map_or("-".to_string(), |v| format!("{v:.1}")),
                    r.bytes_per_step as f64 / 1e6,
                    ms(r.floor_ms),
                    r.over_floor
                        .map_or("n/a".to_string(), |v| format!("{v:.2}x")),
                    r.over_collider_free
                        .map_or("-".to_string(), |v| format!("{v:.2}x")),
                    100.0 * r.touching as f64 / r.blades as f64
                );
            }
            println!("wrote {}", path.display());
            Ok(())
        }
        Command::Reproduce { out, quick, device } => {
            let started = std::time::Instant::now();
            let rendered = meadow::commands::reproduce::reproduce(
                &out,
                quick,
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
        Command::Trace {
            scene,
            seconds,
            every,
            blades,
            wind,
            diagram_from,
            seed,
            coupling,
            out,
            device,
        } => {
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
            let report = trace_to_dir(&request, &out, &mut |done, _| {
                bar.set_position(done);
                signal.load(Ordering::SeqCst) == 0
            });
            bar.finish_and_clear();
            let report = report?;
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
            println!(
                "wrote {} and {}",
                out.join(&report.csv).display(),
                out.join(meadow::commands::trace::REPORT_NAME).display()
            );
            let sig = signal.load(Ordering::SeqCst) as i32;
            if report.interrupted {
                eprintln!(
                    "meadow: interrupted after {} of {} samples' time; the files written are complete",
                    report.samples,
                    report.steps / report.every as u64 + 1
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
        Command::Devices { device } => {
            let (devices, validation) = meadow::commands::devices::devices(&device.options()?)
                .context("listing Vulkan devices")?;
            if devices.is_empty() {
                anyhow::bail!(meadow::Error::NoDevice);
            }
            for d in &devices {
                println!("{}", meadow::commands::devices::line(d));
            }
            if validation.enabled {
                println!(
                    "validation: {} errors, {} warnings",
                    validation.errors, validation.warnings
                );
                validation.check()?;
            }
            Ok(())
        }
        Command::Scenes { print: Some(name) } => {
            print!("{}", meadow::commands::scenes::print(&name)?);
            Ok(())
        }
        Command::Scenes { print: None } => {
            print!("{}", meadow::commands::scenes::list()?);
            Ok(())
        }
    }
}
