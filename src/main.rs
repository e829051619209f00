//! The `meadow` command line: parses, dispatches to the command's own file
//! under src/cli/, and prints an error as one line (exit 1, or 128 + the
//! signal's number when one stopped the work).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cli;

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

#[derive(Subcommand)]
enum Command {
    /// Simulate and render a scene offscreen: DIR/frame_0000.png ... and
    /// DIR/report.json.
    Render(cli::render::RenderArgs),
    /// The meadow live in a window: both phases every frame, simulated
    /// time following the clock. Keys: W A S D Q E fly, drag to look,
    /// wheel speed; space pause, . step, [ ] time slower/faster, L LOD,
    /// V views, P screenshot (DIR/view_NNNN.png), arrows steer the wind,
    /// click drops a gust, B a ball (right click rolls it there), O
    /// overlay, H keys, Esc quit.
    View(cli::view::ViewArgs),
    /// Run the wind solver (with two-way coupling, the grass too); write
    /// two slices of the field as SVG (wind_horizontal.svg,
    /// wind_vertical.svg) and wind_report.json, print speeds, divergence
    /// and GPU time per step.
    Wind(cli::wind::WindArgs),
    /// The paper's Table 1 on this device: the table1 scene at each blade
    /// count, with and without LOD, every frame phase timed on the GPU, plus
    /// the vertex+fragment floor; writes DIR/bench.json, bench.md, bench.svg.
    Bench(cli::bench::BenchArgs),
    /// Time the grass step alone on the GPU (timestamp queries) at several
    /// blade counts, beside the paper's figures; writes DIR/grass_bench.json.
    BenchGrass(cli::bench_grass::BenchGrassArgs),
    /// Render every figure scene of the paper (Fig. 10-13) and write
    /// DIR/index.md and a self-contained DIR/index.html beside the paper's
    /// descriptions and the parameters used.
    Reproduce(cli::reproduce::ReproduceArgs),
    /// Simulate a scene (no rendering) and write the grass's motion as
    /// data: DIR/blades.csv (time_s, blade, root, tip, swing, bend, twist
    /// per traced blade per sample), DIR/trace.json (columns, units, scene,
    /// seed, device, dt) and DIR/space_time.svg (the motion along x over
    /// time: travelling gusts are diagonal stripes).
    Trace(cli::trace::TraceArgs),
    /// List the Vulkan devices and whether each can run meadow.
    Devices(cli::devices::DevicesArgs),
    /// List the built-in scenes; with --print NAME, write one as TOML to
    /// stdout (a start for a scene of one's own).
    Scenes(cli::scenes::ScenesArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => return cli::refuse(&e),
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<cli::Interrupted>() => {
            let cli::Interrupted(sig) = e.downcast_ref::<cli::Interrupted>().expect("checked");
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
        Command::Render(args) => cli::render::run(args),
        Command::View(args) => cli::view::run(args),
        Command::Wind(args) => cli::wind::run(args),
        Command::Bench(args) => cli::bench::run(args),
        Command::BenchGrass(args) => cli::bench_grass::run(args),
        Command::Reproduce(args) => cli::reproduce::run(args),
        Command::Trace(args) => cli::trace::run(args),
        Command::Devices(args) => cli::devices::run(args),
        Command::Scenes(args) => cli::scenes::run(args),
    }
}
