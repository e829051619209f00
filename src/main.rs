//! The `meadow` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Parser, Subcommand, ValueEnum};

use meadow::gpu::{Gpu, GpuOptions, ValidationOptions};
use meadow::job::{render_to_dir, RenderRequest};
use meadow::render::ViewMode;
use meadow::scene::{self, Scene};

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
}

impl DeviceArgs {
    fn options(&self) -> GpuOptions {
        GpuOptions {
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
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene offscreen to DIR/frame_0000.png and DIR/report.json.
    Render {
        /// Built-in scene: few-bunches, several-bunches or meadow.
        #[arg(long, default_value = "meadow")]
        scene: String,
        /// Total number of blades (shared among the scene's patches).
        #[arg(long)]
        blades: Option<usize>,
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
        /// MSAA samples asked for; the largest supported count up to it is used.
        #[arg(long, default_value_t = 8)]
        msaa: u32,
        /// Level of detail: tessellation level 20/10/3 by distance, or always 20.
        #[arg(long, value_enum, default_value = "on")]
        lod: OnOff,
        /// What to show: the shaded grass, or a debug view.
        #[arg(long, value_enum, default_value = "shaded")]
        view: ViewMode,
        /// Random seed of the grass field (default: the scene's).
        #[arg(long)]
        seed: Option<u64>,
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// List the Vulkan devices and whether each can run meadow.
    Devices {
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// List the built-in scenes.
    Scenes,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the cause chain, outermost first.
            let msg: Vec<String> = e.chain().map(|c| c.to_string()).collect();
            eprintln!("meadow: error: {}", msg.join(": "));
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render {
            scene,
            blades,
            width,
            height,
            msaa,
            lod,
            view,
            seed,
            out,
            device,
        } => {
            let mut scene = Scene::builtin(&scene)?;
            if let Some(n) = blades {
                scene.set_blade_count(n)?;
            }
            if let Some(s) = seed {
                scene.seed = s;
            }
            scene.lod.enabled = lod == OnOff::On;
            let request = RenderRequest {
                scene,
                width,
                height,
                msaa,
                view,
                gpu: device.options(),
            };
            let report = render_to_dir(&request, &out)?;
            println!(
                "rendered {} ({} blades, {}x{}, MSAA {}x of {}x asked, LOD {}) on {} [{}] in {:.1} s",
                report.scene,
                report.blades,
                report.width,
                report.height,
                report.msaa_used,
                report.msaa_requested,
                if report.lod { "on" } else { "off" },
                report.device,
                report.device_type,
                report.wall_seconds
            );
            if let Some(s) = &report.pipeline_statistics {
                println!(
                    "grass: {} patches, {} tessellation-evaluation invocations, {} geometry-shader invocations (segments), {} primitives",
                    s.tessellation_control_patches,
                    s.tessellation_evaluation_invocations,
                    s.geometry_shader_invocations,
                    s.geometry_shader_primitives
                );
            }
            if report.validation.enabled {
                println!(
                    "validation: {} errors, {} warnings",
                    report.validation.errors, report.validation.warnings
                );
            }
            println!("wrote {}", out.join("frame_0000.png").display());
            Ok(())
        }
        Command::Devices { device } => {
            let devices = Gpu::list_devices(&device.options()).context("listing Vulkan devices")?;
            if devices.is_empty() {
                anyhow::bail!(meadow::Error::NoDevice);
            }
            for d in devices {
                println!(
                    "{}  [{}]  Vulkan {}  {}  max MSAA {}x  {}",
                    d.name,
                    d.device_type,
                    d.api_version,
                    d.driver,
                    d.max_msaa,
                    match &d.missing {
                        None => "qualifies".to_string(),
                        Some(f) => format!("does not qualify: lacks {f}"),
                    }
                );
            }
            Ok(())
        }
        Command::Scenes => {
            for name in scene::BUILTIN {
                let s = Scene::builtin(name)?;
                println!("{name}  ({} blades)", s.blade_count());
            }
            Ok(())
        }
    }
}
