//! The `meadow` command line: parses (the command tree is src/cli/'s
//! `Cli`), dispatches to the command's own file under src/cli/, and prints
//! an error as one line (exit 2 for a refused command line, 1 for failed
//! work, or 128 + the signal's number when one stopped the work).

use std::process::ExitCode;

use clap::Parser;

mod cli;

use cli::{Cli, Command};

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
        Command::GpuReport(args) => cli::gpu_report::run(args),
        Command::Reproduce(args) => cli::reproduce::run(args),
        Command::Trace(args) => cli::trace::run(args),
        Command::Devices(args) => cli::devices::run(args),
        Command::Scenes(args) => cli::scenes::run(args),
    }
}
