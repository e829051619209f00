//! The command line: the command tree (`Cli`), each `meadow` command's
//! arguments and what it prints (one file per command, beside the
//! library's src/commands/), and what they share: the device and scene
//! arguments, numbers read in words (numbers.rs), one-line refusals, and
//! stopping on a signal. main.rs parses and dispatches; the library does
//! the work.

use std::sync::atomic::AtomicUsize;
use std::sync::Arc;

use anyhow::Context as _;
use clap::{Parser, Subcommand, ValueEnum};

use meadow::gpu::{FaultPlan, GpuOptions, ValidationOptions};
use meadow::model::wind::Coupling;
use meadow::scene::{Scene, ViewMode};

/// The largest image side any flag takes (the device may allow less).
const MAX_SIDE: u64 = meadow::scene::check::MAX_IMAGE_SIDE as u64;

pub mod bench;
pub mod bench_grass;
pub mod devices;
pub mod gpu_report;
pub mod numbers;
pub mod render;
pub mod reproduce;
pub mod scenes;
pub mod trace;
pub mod view;
pub mod wind;

#[cfg(test)]
mod tests;

/// The command line: `meadow COMMAND [FLAGS]`.
#[derive(Parser)]
#[command(
    name = "meadow",
    version,
    about = "Grass swaying in dynamic wind (Lee et al. 2016) on Vulkan"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Simulate and render a scene offscreen: DIR/frame_0000.png ... and
    /// DIR/report.json.
    Render(render::RenderArgs),
    /// The meadow live in a window: both phases every frame, simulated
    /// time following the clock. Keys: W A S D Q E fly, drag to look,
    /// wheel speed; space pause, . step, [ ] time slower/faster, L LOD,
    /// V views, P screenshot (DIR/view_NNNN.png), arrows steer the wind,
    /// click drops a gust, B a ball (right click rolls it there), O
    /// overlay, H keys, Esc quit.
    View(view::ViewArgs),
    /// Run the wind solver (with two-way coupling, the grass too); write
    /// two slices of the field as SVG (wind_horizontal.svg,
    /// wind_vertical.svg), the field for analysis (wind_field.npy) and
    /// wind_report.json, print speeds, divergence and GPU time per step.
    Wind(wind::WindArgs),
    /// The paper's Table 1 on this device: the table1 scene at each blade
    /// count, with and without LOD, every frame phase timed on the GPU, plus
    /// the vertex+fragment floor; writes DIR/bench.json, bench.md, bench.svg.
    Bench(bench::BenchArgs),
    /// Time the grass step alone on the GPU (timestamp queries) at several
    /// blade counts, beside the paper's figures; writes DIR/grass_bench.json.
    BenchGrass(bench_grass::BenchGrassArgs),
    /// Every figure whose speed matters on this device, in one run: bench
    /// (with and without culling and LOD), bench-grass (with its memory
    /// floor, and with colliders), the wind step (both solvers, two-way
    /// coupling), frames of prairie and roll, each command once under
    /// validation; writes DIR/<device>.md and .json with the GPU targets
    /// of docs/perf.md met or missed. scripts/gpu-report runs it.
    GpuReport(gpu_report::GpuReportArgs),
    /// Render every figure scene of the paper (Fig. 10-13) and write
    /// DIR/index.md and a self-contained DIR/index.html beside the paper's
    /// descriptions and the parameters used.
    Reproduce(reproduce::ReproduceArgs),
    /// Simulate a scene (no rendering) and write the grass's motion as
    /// data: DIR/blades.csv (time_s, blade, root, tip, swing, bend, twist
    /// per traced blade per sample), DIR/trace.json (columns, units, scene,
    /// seed, device, dt, the tips' spectrum), DIR/space_time.svg (the
    /// motion along the wind over time: travelling gusts are diagonal stripes),
    /// DIR/plan_view.svg (the field from above at three instants a second
    /// apart: patches of turbulence moving downwind) and DIR/spectrum.svg
    /// (the tips' spectrum beside the blades' natural frequencies).
    Trace(trace::TraceArgs),
    /// List the Vulkan devices and whether each can run meadow.
    Devices(devices::DevicesArgs),
    /// List the built-in scenes; with --print NAME, write one as TOML to
    /// stdout (a start for a scene of one's own).
    Scenes(scenes::ScenesArgs),
}

/// `--overwrite`, for every command that writes into an `--out` folder.
#[derive(clap::Args)]
pub struct OverwriteArg {
    /// Replace files in the --out folder that an earlier meadow run there
    /// did not write, or that were changed since (without it such a run is
    /// refused before any work; other files are never touched).
    #[arg(long)]
    pub overwrite: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LodArg {
    Both,
    On,
    Off,
}

#[derive(clap::Args)]
pub struct DeviceArgs {
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
    #[arg(long, value_name = "MIB", allow_negative_numbers = true, value_parser = numbers::whole::<u64>(1, 16_777_216))]
    gpu_memory_mib: Option<u64>,
}

impl DeviceArgs {
    /// The same choices as arguments again, for a child meadow process
    /// (`bench --against`).
    pub fn to_args(&self) -> Vec<String> {
        let mut args = Vec::new();
        if let Some(device) = &self.device {
            args.extend(["--device".to_string(), device.clone()]);
        }
        if self.validation {
            args.push("--validation".into());
        }
        if self.best_practices {
            args.push("--best-practices".into());
        }
        if let Some(mib) = self.gpu_memory_mib {
            args.extend(["--gpu-memory-mib".to_string(), mib.to_string()]);
        }
        args
    }

    pub fn options(&self) -> anyhow::Result<GpuOptions> {
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
            // A test hook: the most bytes one storage binding may reach,
            // so that the kernels run in batches on a small meadow.
            storage_range: storage_range_hook()?,
            window_extensions: Vec::new(),
            // A test hook: fail the N-th allocation or submission.
            faults: FaultPlan::parse(&std::env::var("MEADOW_INJECT_FAULT").unwrap_or_default())?,
        })
    }
}

/// MEADOW_STORAGE_RANGE, when set: bytes, a whole number.
fn storage_range_hook() -> anyhow::Result<Option<u32>> {
    match std::env::var("MEADOW_STORAGE_RANGE") {
        Err(_) => Ok(None),
        Ok(v) => v.parse().map(Some).map_err(|_| {
            anyhow::anyhow!(
                "MEADOW_STORAGE_RANGE is {v:?}: give the bytes one storage binding may reach, a whole number, or unset it"
            )
        }),
    }
}

/// A render stopped by a signal: the process exits 128 + its number (130
/// for SIGINT, 143 for SIGTERM), as a shell reports a process killed by it.
#[derive(Debug)]
pub struct Interrupted(pub i32);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted by {}", signal_name(self.0))
    }
}

impl std::error::Error for Interrupted {}

pub fn signal_name(signal: i32) -> &'static str {
    match signal {
        signal_hook::consts::SIGINT => "SIGINT (Ctrl-C)",
        signal_hook::consts::SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}

/// SIGINT and SIGTERM stored as their number when they arrive (0 until
/// then): the handlers only store it (async-signal-safe); the long
/// commands poll it between steps and stop cleanly.
pub fn stop_signal() -> anyhow::Result<Arc<AtomicUsize>> {
    let signal = Arc::new(AtomicUsize::new(0));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_usize(sig, signal.clone(), sig as usize)
            .context("installing the SIGINT/SIGTERM handlers")?;
    }
    Ok(signal)
}

/// The scene and what `render` and `view` may change of it from the
/// command line.
#[derive(clap::Args)]
pub struct SceneArgs {
    /// A built-in scene (`meadow scenes` lists them) or a scene file (.toml).
    #[arg(long, default_value = "table1")]
    scene: String,
    /// Total number of blades, shared among the scene's patches (200000,
    /// 200k, 1.5m).
    #[arg(long, allow_hyphen_values = true)]
    blades: Option<String>,
    /// Width in pixels of the image (render) or of the window at the start
    /// (view); default: the scene's [render] width.
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_SIDE))]
    width: Option<u32>,
    /// Height in pixels, as --width (default: the scene's [render] height).
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_SIDE))]
    height: Option<u32>,
    /// MSAA samples asked for; the largest supported count up to it is used.
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, 64))]
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
    #[arg(long, allow_negative_numbers = true, value_parser = numbers::seed)]
    seed: Option<u64>,
    /// Whether the grass slows the wind: one-way (the paper's) or
    /// two-way (canopy drag; default: the scene's wind.coupling).
    #[arg(long, value_enum)]
    coupling: Option<Coupling>,
    /// Shadow map side in texels (default: the scene's, the paper's 8192;
    /// smaller for quick previews; 0 turns shadows off).
    #[arg(long, value_name = "TEXELS", allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, MAX_SIDE))]
    shadow_map: Option<u32>,
}

impl SceneArgs {
    /// The scene loaded, with the overrides applied (size, MSAA and view
    /// are the caller's: they go to the request, not the scene).
    pub fn load(&self) -> anyhow::Result<Scene> {
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

/// A command line clap refused, as one line: a value refused by its flag's
/// parser as "--flag VALUE is not allowed, use ..." (the library's own
/// refusals read the same), anything else as clap's first line with its
/// tip, if it has one (e.g. "did you mean '--frames'?").
pub fn parse_error_line(e: &clap::Error) -> String {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let context = |kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        _ => None,
    };
    let rendered = e.render().to_string();
    let mut lines = rendered.lines().map(str::trim).filter(|l| !l.is_empty());
    let first = lines.next().unwrap_or("the command line was refused");
    let first = first.strip_prefix("error: ").unwrap_or(first);
    if e.kind() == ErrorKind::ValueValidation {
        if let (Some(arg), Some(value)) = (
            context(ContextKind::InvalidArg),
            context(ContextKind::InvalidValue),
        ) {
            // "--frames <FRAMES>" names the flag as "--frames".
            let flag = arg.split(' ').next().unwrap_or(&arg);
            if let Some(fix) = first.rsplit_once("': ").map(|(_, fix)| fix) {
                return format!("{flag} {value} is not allowed, {fix}");
            }
        }
    }
    // The allowed values and clap's suggestion, if it has them.
    let mut line = first.to_string();
    for more in lines {
        if let Some(tip) = more.strip_prefix("tip: ") {
            line.push_str(&format!(" ({tip})"));
        } else if more.starts_with("[possible values") {
            line.push_str(&format!(" {more}"));
        }
    }
    line
}

/// Prints a refused command line as one line; clap's exit status for a
/// usage error.
pub fn refuse(e: &clap::Error) -> std::process::ExitCode {
    eprintln!("meadow: error: {}", parse_error_line(e));
    std::process::ExitCode::from(2)
}

/// `--blades` as every command reads it: 1200, 50k, 1.5m. A plain
/// number is passed on as it is, for the scene to refuse by range.
pub fn blade_count(text: &str) -> anyhow::Result<usize> {
    match text.trim().parse::<usize>() {
        Ok(n) => Ok(n),
        Err(_) => Ok(meadow::commands::bench_grass::parse_count(text)?),
    }
}
