//! `meadow bench`: its arguments, and what it prints of the
//! library's work (src/commands/bench.rs).

use std::path::PathBuf;

use meadow::scene::Scene;

use meadow::commands::bench::against::{AgainstRequest, MAX_AGAINST_RUNS};
use meadow::commands::bench::{BenchStep, MAX_BENCH_FRAMES};
use meadow::scene::check::MAX_IMAGE_SIDE;

use super::{numbers, DeviceArgs, LodArg, OnOff, OverwriteArg};

#[derive(clap::Args)]
pub struct BenchArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "table1")]
    scene: String,
    /// Blade counts, comma-separated (50k, 1.5m, 1200); counts past 200K
    /// run when asked, after a check that they fit the GPU's memory.
    #[arg(long, default_value = "50k,100k,150k,200k")]
    blades: String,
    /// Rows with level of detail on, off, or both.
    #[arg(long, value_enum, default_value = "both")]
    lod: LodArg,
    /// Timed frames per row (each one simulation step).
    #[arg(long, default_value_t = 20, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_BENCH_FRAMES as u64))]
    frames: u32,
    /// Untimed frames before them.
    #[arg(long, default_value_t = 3, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, MAX_BENCH_FRAMES as u64))]
    warmup: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_IMAGE_SIDE as u64))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_IMAGE_SIDE as u64))]
    height: u32,
    /// MSAA samples asked for (the paper's 8; the largest supported up
    /// to this is used and reported).
    #[arg(long, default_value_t = 8, allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, 64))]
    msaa: u32,
    /// Shadow map side in texels (default: the scene's, the paper's 8192;
    /// 0 turns shadows off).
    #[arg(long, value_name = "TEXELS", allow_negative_numbers = true, value_parser = numbers::whole::<u32>(0, MAX_IMAGE_SIDE as u64))]
    shadow_map: Option<u32>,
    /// Wind grid cells X,Y,Z, y up (default: the scene's, table1's the
    /// paper's 60,20,60).
    #[arg(long, value_name = "X,Y,Z")]
    cells: Option<String>,
    /// Occlusion culling in the rows with culling on (default: the
    /// scene's [cull] occlusion, off).
    #[arg(long, value_enum)]
    occlusion: Option<OnOff>,
    /// Each frame's steps beside the drawing of the frame before (default:
    /// the scene's render.overlap, auto: where the device has a second
    /// queue).
    #[arg(long, value_enum)]
    overlap: Option<meadow::scene::Overlap>,
    /// Also run each row with the scene's terrain made flat (the same
    /// blades on flat ground): bench.md's terrain table sets them side by
    /// side. Needs a scene with terrain (hills).
    #[arg(long)]
    also_flat: bool,
    /// Time an older meadow binary beside this one: the same bench run by
    /// each in turn, --runs times, alternating; prints each phase's new /
    /// old ratio and writes against.json and against.md to --out.
    #[arg(long, value_name = "OLD_BINARY")]
    against: Option<PathBuf>,
    /// With --against: runs of each binary.
    #[arg(long, default_value_t = 3, requires = "against", allow_negative_numbers = true, value_parser = numbers::whole::<u32>(1, MAX_AGAINST_RUNS as u64))]
    runs: u32,
    /// Folder for bench.json, bench.md and bench.svg (made if missing).
    #[arg(long, default_value = "out/bench")]
    out: PathBuf,
    #[command(flatten)]
    overwrite: OverwriteArg,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    if let Some(old) = args.against.clone() {
        return run_against(old, &args);
    }
    let out = args.out.clone();
    let overwrite = args.overwrite.overwrite;
    let request = request(args)?;
    // A bar on a terminal (indicatif draws nothing when stderr is not one).
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len}  {msg}  {elapsed} elapsed")
            .expect("a valid progress template"),
    );
    let bench = meadow::commands::bench::bench_to_dir(&request, &out, overwrite, &mut |p| {
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(step_message(&p.next));
    });
    bar.finish_and_clear();
    let bench = bench?;
    print!("{}", meadow::commands::bench::markdown(&bench));
    println!(
        "wrote {}, bench.md and bench.svg",
        out.join("bench.json").display()
    );
    Ok(())
}

/// The bench the arguments ask for: the scene with its overrides, the
/// rows' blade counts.
fn request(args: BenchArgs) -> anyhow::Result<meadow::commands::bench::BenchRequest> {
    let BenchArgs {
        scene,
        blades,
        lod,
        frames,
        warmup,
        width,
        height,
        msaa,
        shadow_map,
        cells,
        occlusion,
        overlap,
        also_flat,
        against: _,
        runs: _,
        out: _,
        overwrite: _,
        device,
    } = args;
    let counts = blades
        .split(',')
        .map(meadow::commands::bench_grass::parse_count)
        .collect::<Result<Vec<_>, _>>()?;
    let mut scene = Scene::load(&scene)?;
    if let Some(n) = shadow_map {
        scene.set_shadow_map(n)?;
    }
    if let Some(cells) = cells {
        scene.set_wind_cells(&cells)?;
    }
    if let Some(occlusion) = occlusion {
        scene.cull.occlusion = occlusion == OnOff::On;
    }
    if let Some(overlap) = overlap {
        scene.render.overlap = overlap;
    }
    Ok(meadow::commands::bench::BenchRequest {
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
        also_flat,
        gpu: device.options()?,
    })
}

/// What the progress bar says the bench times next.
fn step_message(next: &BenchStep) -> String {
    let on = |b: bool| if b { "on" } else { "off" };
    match *next {
        BenchStep::Solvers => "timing the wind step with each pressure solver".to_string(),
        BenchStep::Row {
            blades,
            lod,
            cull,
            terrain,
        } => format!(
            "timing frames at {blades} blades, LOD {}, culling {}{}",
            on(lod),
            on(cull),
            if terrain { "" } else { ", flat ground" }
        ),
    }
}

/// `--against OLD_BINARY`: the same bench, as arguments for each binary,
/// run by the old and this one in turn; prints each phase's ratio.
fn run_against(old: PathBuf, args: &BenchArgs) -> anyhow::Result<()> {
    // The same bench, as arguments for each binary.
    let mut bench_args: Vec<String> = [
        "bench",
        "--scene",
        &args.scene,
        "--blades",
        &args.blades,
        "--lod",
    ]
    .map(String::from)
    .to_vec();
    bench_args.push(
        match args.lod {
            LodArg::Both => "both",
            LodArg::On => "on",
            LodArg::Off => "off",
        }
        .into(),
    );
    for (flag, value) in [
        ("--frames", args.frames),
        ("--warmup", args.warmup),
        ("--width", args.width),
        ("--height", args.height),
        ("--msaa", args.msaa),
    ] {
        bench_args.extend([flag.to_string(), value.to_string()]);
    }
    if let Some(n) = args.shadow_map {
        bench_args.extend(["--shadow-map".to_string(), n.to_string()]);
    }
    if let Some(cells) = &args.cells {
        bench_args.extend(["--cells".to_string(), cells.clone()]);
    }
    if let Some(o) = args.occlusion {
        let o = if o == OnOff::On { "on" } else { "off" };
        bench_args.extend(["--occlusion".to_string(), o.to_string()]);
    }
    if let Some(o) = args.overlap {
        bench_args.extend(["--overlap".to_string(), o.to_string()]);
    }
    if args.also_flat {
        bench_args.push("--also-flat".into());
    }
    bench_args.extend(args.device.to_args());
    let request = AgainstRequest {
        old,
        new: std::env::current_exe()?,
        bench_args,
        runs: args.runs,
    };
    let against = meadow::commands::bench::against::bench_against(
        &request,
        &args.out,
        args.overwrite.overwrite,
        &mut |done, total, which| {
            eprintln!("meadow: bench {}/{total}: the {which} binary", done + 1)
        },
    )?;
    print!("{}", meadow::commands::bench::against::markdown(&against));
    println!("wrote {}", args.out.join("against.json").display());
    Ok(())
}
