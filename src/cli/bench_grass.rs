//! `meadow bench-grass`: its arguments, and what it prints of the
//! library's work (src/commands/bench_grass.rs).

use std::path::PathBuf;

use meadow::scene::Scene;

use super::{numbers, DeviceArgs, OverwriteArg};

/// What bench-grass writes into --out.
const REPORT_NAME: &str = "grass_bench.json";

#[derive(clap::Args)]
pub struct BenchGrassArgs {
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
    #[arg(long, default_value_t = 30, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, 10_000))]
    steps: u32,
    /// Untimed grass steps before timing.
    #[arg(long, default_value_t = 5, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, 10_000))]
    warmup: u32,
    /// Wind steps solved before the grass steps, untimed, so that the
    /// grass meets a developed field.
    #[arg(long, default_value_t = meadow::commands::bench_grass::WIND_WARMUP_STEPS, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, 10_000))]
    wind_warmup: u32,
    /// Folder for grass_bench.json (made if missing).
    #[arg(long, default_value = "out/bench-grass")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: BenchGrassArgs) -> anyhow::Result<()> {
    let BenchGrassArgs {
        scene,
        blades,
        colliders,
        steps,
        warmup,
        wind_warmup,
        out,
        overwrite,
        device,
    } = args;
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
    let claim = meadow::report::claim::OutputClaim::new(
        &out,
        &[REPORT_NAME.to_string()],
        overwrite.overwrite,
    )?;
    // A bar on a terminal (indicatif draws nothing when stderr is not one):
    // a row at 10M blades runs for minutes on lavapipe.
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len}  {msg}  {elapsed} elapsed")
            .expect("a valid progress template"),
    );
    let bench = meadow::commands::bench_grass::bench_grass(
        &scene,
        &counts,
        &colliders,
        meadow::commands::bench_grass::GrassSteps {
            timed: steps,
            warmup,
            wind_warmup,
        },
        &device.options()?,
        &mut |p| {
            bar.set_length(p.total as u64);
            bar.set_position(p.done as u64);
            bar.set_message(match p.row {
                Some((blades, 0)) => format!("timing the grass step at {blades} blades"),
                Some((blades, c)) => {
                    format!("timing the grass step at {blades} blades, {c} colliders")
                }
                None => "measuring the copy bandwidth (the memory floor)".to_string(),
            });
        },
    );
    bar.finish_and_clear();
    let bench = bench?;
    claim.begin()?;
    claim.write_json(REPORT_NAME, &bench)?;
    print_table(&bench, steps);
    println!("wrote {}", out.join(REPORT_NAME).display());
    Ok(())
}

/// The rows as a table on stdout, with the device and the memory floor.
fn print_table(bench: &meadow::commands::bench_grass::GrassBench, steps: u32) {
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
}
