//! `meadow gpu-report`: every figure whose speed matters, on this device, in
//! one run: the frame (`bench`, with and without culling and level of
//! detail), the grass step and its memory floor (`bench-grass`), the grass
//! step with colliders, the wind step with both pressure solvers and with
//! two-way coupling (`wind`), frames of `prairie` and `roll` (`render`),
//! and each of those commands once more, small, under strict validation
//! (core and synchronization) with its errors counted. The figures go to
//! `<out>/<device>.json` and `.md` beside the GPU targets of docs/perf.md,
//! each met, missed or not measured; the commands' own outputs go to a
//! work folder. `--quick` runs the same set at sizes lavapipe finishes in
//! minutes (its figures are not the targets' and say so).
//!
//! This file runs the parts; `targets.rs` judges the targets and
//! `markdown.rs` writes the tables, each using only this file's types.

use std::path::{Path, PathBuf};

use crate::commands::bench::{bench_to_dir, BenchRequest, LodChoice};
use crate::commands::bench_grass::{bench_grass, GrassBench, GrassSteps, WIND_WARMUP_STEPS};
use crate::commands::on_gpu;
use crate::commands::render::{render_to_dir, Animation, RenderRequest};
use crate::commands::wind::{wind_to_dir, WindReport};
use crate::error::Result;
use crate::frame::timing::TimingSummary;
use crate::gpu::{GpuOptions, ValidationOptions};
use crate::model::wind::{Coupling, PressureSolver};
use crate::report::bench::Bench;
use crate::report::claim::OutputClaim;
use crate::report::files;
use crate::scene::{Scene, ViewMode};

mod markdown;
mod targets;

use markdown::markdown;
use targets::targets;

/// What to run and where.
#[derive(Clone, Debug)]
pub struct GpuReportRequest {
    /// The reduced set (lavapipe in minutes) instead of the targets' sizes.
    pub quick: bool,
    /// Where the commands' own outputs go (each in a folder of its own).
    pub work: PathBuf,
    /// Replace what an earlier run in `work` (and the report in `out`)
    /// did not write.
    pub overwrite: bool,
    /// The device and memory budget; validation is this command's own.
    pub gpu: GpuOptions,
}

/// The sizes of one run.
struct Plan {
    quick: bool,
    bench_counts: Vec<usize>,
    bench_frames: u32,
    bench_warmup: u32,
    width: u32,
    height: u32,
    msaa: u32,
    shadow_map: u32,
    grass_counts: Vec<usize>,
    collider_counts: Vec<usize>,
    colliders: Vec<usize>,
    grass_steps: u32,
    grass_warmup: u32,
    /// Wind steps before bench-grass's rows (`GrassSteps::wind_warmup`).
    wind_warmup: u32,
    wind_steps: u32,
    scene_frames: u32,
    /// `prairie`'s blades (None: the scene's 2 million).
    prairie_blades: Option<usize>,
    /// The validated runs: blades, image size and frames.
    check_blades: usize,
    check_size: (u32, u32),
    check_steps: u32,
}

fn plan(quick: bool) -> Plan {
    if quick {
        Plan {
            quick: true,
            bench_counts: vec![2_000],
            bench_frames: 2,
            bench_warmup: 1,
            width: 320,
            height: 180,
            msaa: 4,
            shadow_map: 1024,
            grass_counts: vec![2_000],
            collider_counts: vec![2_000],
            colliders: vec![0, 16],
            grass_steps: 4,
            grass_warmup: 1,
            wind_warmup: 2,
            wind_steps: 6,
            scene_frames: 2,
            prairie_blades: Some(20_000),
            check_blades: 2_000,
            check_size: (160, 90),
            check_steps: 3,
        }
    } else {
        Plan {
            quick: false,
            bench_counts: vec![200_000, 1_000_000],
            bench_frames: 20,
            bench_warmup: 3,
            width: 1280,
            height: 720,
            msaa: 8,
            shadow_map: 8192,
            grass_counts: vec![200_000, 1_000_000, 10_000_000],
            collider_counts: vec![200_000, 1_000_000],
            colliders: vec![0, 16, 128],
            grass_steps: 30,
            grass_warmup: 5,
            wind_warmup: WIND_WARMUP_STEPS,
            wind_steps: 300,
            scene_frames: 20,
            prairie_blades: None,
            check_blades: 50_000,
            check_size: (640, 360),
            check_steps: 30,
        }
    }
}

/// A part of the report: its figures, or why there are none (a part that
/// fails does not stop the others).
#[derive(Clone, Debug, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome<T> {
    Ran(T),
    Failed(String),
}

impl<T> Outcome<T> {
    fn of(result: Result<T>) -> Self {
        match result {
            Ok(v) => Outcome::Ran(v),
            Err(e) => Outcome::Failed(e.to_string()),
        }
    }

    pub fn ran(&self) -> Option<&T> {
        match self {
            Outcome::Ran(v) => Some(v),
            Outcome::Failed(_) => None,
        }
    }

    pub fn failure(&self) -> Option<&str> {
        match self {
            Outcome::Ran(_) => None,
            Outcome::Failed(e) => Some(e),
        }
    }
}

/// Frames of a shipped scene through `meadow render`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SceneFrames {
    pub scene: String,
    pub blades: usize,
    pub width: u32,
    pub height: u32,
    pub msaa_used: u32,
    pub frames: usize,
    pub timing: TimingSummary,
    pub wall_seconds: f64,
}

/// One command run small under strict validation.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ValidatedRun {
    pub command: String,
    /// Errors and warnings the layer reported (`errors` must be 0), or why
    /// the run failed (a validation error fails it, naming the message).
    pub outcome: Outcome<ValidationCount>,
}

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ValidationCount {
    pub errors: u64,
    pub warnings: u64,
}

impl ValidationCount {
    fn of(report: &crate::gpu::ValidationReport) -> Self {
        Self {
            errors: report.errors,
            warnings: report.warnings,
        }
    }
}

/// A GPU target of docs/perf.md against what this run measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Target {
    pub name: String,
    /// What is asked, in words.
    pub target: String,
    /// The figure compared (in `unit`), None where not measured.
    pub measured: Option<f64>,
    pub unit: String,
    /// None where not measured.
    pub met: Option<bool>,
    /// Where the figure comes from, or why there is none.
    pub note: String,
}

/// docs/bench/<device>.json.
#[derive(Clone, Debug, serde::Serialize)]
pub struct GpuReport {
    pub device: String,
    pub device_type: String,
    pub driver: String,
    pub api_version: String,
    pub meadow_version: String,
    /// The commit the binary was built from (build.rs; "unknown" outside
    /// a git checkout).
    pub commit: String,
    /// When the run ended (UTC, RFC 3339).
    pub date: String,
    pub quick: bool,
    pub wall_seconds: f64,
    pub targets: Vec<Target>,
    pub bench: Outcome<Bench>,
    pub grass: Outcome<GrassBench>,
    pub colliders: Outcome<GrassBench>,
    pub wind: Outcome<WindReport>,
    pub wind_two_way: Outcome<WindReport>,
    pub frames: Vec<Outcome<SceneFrames>>,
    pub validation: Vec<ValidatedRun>,
}

impl GpuReport {
    /// Runs that failed or that validation found errors in, one line each.
    pub fn failures(&self) -> Vec<String> {
        let mut out = Vec::new();
        let parts = [
            ("bench", self.bench.failure()),
            ("bench-grass", self.grass.failure()),
            ("bench-grass --colliders", self.colliders.failure()),
            ("wind", self.wind.failure()),
            ("wind --coupling two-way", self.wind_two_way.failure()),
        ];
        let frames = self.frames.iter().map(|f| ("render", f.failure()));
        for (name, e) in parts.into_iter().chain(frames) {
            if let Some(e) = e {
                out.push(format!("{name}: {e}"));
            }
        }
        for v in &self.validation {
            match &v.outcome {
                Outcome::Ran(c) if c.errors > 0 => {
                    out.push(format!("{} (validated): {} errors", v.command, c.errors))
                }
                Outcome::Ran(_) => {}
                Outcome::Failed(e) => out.push(format!("{} (validated): {e}", v.command)),
            }
        }
        out
    }
}

/// The file name a device's report takes: its name in lower case, words
/// joined by '-', without what it says in parentheses ("NVIDIA H100 80GB
/// HBM3" -> "nvidia-h100-80gb-hbm3", "llvmpipe (LLVM 15.0.6, 256 bits)"
/// -> "llvmpipe").
pub fn device_file_stem(device: &str) -> String {
    let plain = device.split('(').next().unwrap_or(device);
    let words: Vec<String> = plain
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_ascii_lowercase)
        .collect();
    if words.is_empty() {
        "device".to_string()
    } else {
        words.join("-")
    }
}

/// Runs everything and writes `<out>/<device>.json` and `.md` (replacing
/// only what an earlier report wrote there, or anything with
/// `overwrite`). `on_part` hears of each part before it starts. The report
/// is written even where a part failed; `GpuReport::failures` says which.
pub fn gpu_report(
    request: &GpuReportRequest,
    out: &Path,
    on_part: &mut dyn FnMut(&str),
) -> Result<(GpuReport, PathBuf)> {
    let started = std::time::Instant::now();
    let p = plan(request.quick);
    files::ensure_dir(out)?;
    files::ensure_dir(&request.work)?;
    // The device first: it names the report, and a device that does not
    // open stops the run here with the reason.
    on_part("opening the device");
    let (info, _) = on_gpu(&request.gpu, |gpu| Ok(gpu.info().clone()))?;
    let stem = device_file_stem(&info.name);
    let planned = vec![format!("{stem}.json"), format!("{stem}.md")];
    let claim = OutputClaim::new(out, &planned, request.overwrite)?;
    let work = |part: &str| request.work.join(part);
    let table1 = Scene::builtin("table1")?;

    on_part("bench: the frame with and without culling and LOD");
    let bench = Outcome::of(run_bench(
        request,
        &p,
        &table1,
        p.bench_counts.clone(),
        &work("bench"),
    ));
    let grass_step = |counts: &[usize], colliders: &[usize]| {
        Outcome::of(bench_grass(
            &table1,
            counts,
            colliders,
            GrassSteps {
                timed: p.grass_steps,
                warmup: p.grass_warmup,
                wind_warmup: p.wind_warmup,
            },
            &request.gpu,
            &mut |_| {},
        ))
    };
    on_part("bench-grass: the grass step and its memory floor");
    let grass = grass_step(&p.grass_counts, &[0]);
    on_part("bench-grass: the grass step with colliders");
    let colliders = grass_step(&p.collider_counts, &p.colliders);
    let (wind, wind_two_way) = wind_parts(request, &p, &table1, on_part);
    let frames = scene_frames(request, &p, on_part);

    let validation = validated_runs(request, &p, &table1, on_part);
    let targets = targets(&p, &bench, &grass, &colliders, &wind);
    let report = GpuReport {
        device: info.name.clone(),
        device_type: info.device_type.clone(),
        driver: info.driver.clone(),
        api_version: info.api_version.clone(),
        meadow_version: env!("CARGO_PKG_VERSION").to_string(),
        commit: env!("MEADOW_COMMIT").to_string(),
        date: humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
        quick: request.quick,
        wall_seconds: started.elapsed().as_secs_f64(),
        targets,
        bench,
        grass,
        colliders,
        wind,
        wind_two_way,
        frames,
        validation,
    };
    claim.begin()?;
    claim.write_json(&planned[0], &report)?;
    claim.write(&planned[1], markdown(&report, &p).as_bytes())?;
    Ok((report, out.join(&planned[1])))
}
/// The wind step with both pressure solvers, one-way and two-way.
fn wind_parts(
    request: &GpuReportRequest,
    p: &Plan,
    table1: &Scene,
    on_part: &mut dyn FnMut(&str),
) -> (Outcome<WindReport>, Outcome<WindReport>) {
    on_part("wind: both pressure solvers");
    let wind = Outcome::of(run_wind(
        request,
        table1,
        Coupling::OneWay,
        p.wind_steps,
        &request.work.join("wind"),
        &request.gpu,
    ));
    on_part("wind: two-way coupling");
    let wind_two_way = Outcome::of(run_wind(
        request,
        table1,
        Coupling::TwoWay,
        p.wind_steps,
        &request.work.join("wind-two-way"),
        &request.gpu,
    ));
    (wind, wind_two_way)
}

/// Frames of `prairie` and `roll` through `render`.
fn scene_frames(
    request: &GpuReportRequest,
    p: &Plan,
    on_part: &mut dyn FnMut(&str),
) -> Vec<Outcome<SceneFrames>> {
    let mut frames = Vec::new();
    for name in ["prairie", "roll"] {
        on_part(&format!("render: frames of {name}"));
        let blades = (name == "prairie").then_some(p.prairie_blades).flatten();
        frames.push(Outcome::of(
            run_frames(
                request,
                name,
                blades,
                (p.width, p.height),
                p.msaa,
                p.scene_frames,
                &request.work.join(format!("frames-{name}")),
                &request.gpu,
            )
            .map(|(frames, _)| frames),
        ));
    }
    frames
}

fn run_bench(
    request: &GpuReportRequest,
    p: &Plan,
    table1: &Scene,
    counts: Vec<usize>,
    dir: &Path,
) -> Result<Bench> {
    let mut scene = table1.clone();
    scene.set_shadow_map(p.shadow_map)?;
    let bench = BenchRequest {
        scene,
        counts,
        lod: LodChoice::Both,
        frames: p.bench_frames,
        warmup: p.bench_warmup,
        width: p.width,
        height: p.height,
        msaa: p.msaa,
        also_flat: false,
        gpu: request.gpu.clone(),
    };
    bench_to_dir(&bench, dir, request.overwrite, &mut |_| {})
}

fn run_wind(
    request: &GpuReportRequest,
    table1: &Scene,
    coupling: Coupling,
    steps: u32,
    dir: &Path,
    gpu: &GpuOptions,
) -> Result<WindReport> {
    let mut scene = table1.clone();
    scene.wind.coupling = coupling;
    wind_to_dir(&scene, steps, gpu, dir, request.overwrite, &mut |_| {})
}

#[allow(clippy::too_many_arguments)]
fn run_frames(
    request: &GpuReportRequest,
    name: &str,
    blades: Option<usize>,
    size: (u32, u32),
    msaa: u32,
    frames: u32,
    dir: &Path,
    gpu: &GpuOptions,
) -> Result<(SceneFrames, ValidationCount)> {
    let mut scene = Scene::builtin(name)?;
    if let Some(n) = blades {
        scene.set_blade_count(n)?;
    }
    let render = RenderRequest {
        scene,
        width: size.0,
        height: size.1,
        msaa,
        view: ViewMode::Shaded,
        animation: Animation {
            frames,
            fps: 30.0,
            start: 0.0,
        },
        every: 1,
        gif: false,
        video: None,
        overwrite: request.overwrite,
        light_waves: false,
        gpu: gpu.clone(),
    };
    let report = render_to_dir(&render, dir)?;
    let validation = ValidationCount::of(&report.validation);
    let frames = SceneFrames {
        scene: name.to_string(),
        blades: report.blades,
        width: report.width,
        height: report.height,
        msaa_used: report.msaa_used,
        frames: report.frames.len(),
        timing: report.timing,
        wall_seconds: report.wall_seconds,
    };
    Ok((frames, validation))
}

/// Each command once more, small, under strict validation.
fn validated_runs(
    request: &GpuReportRequest,
    p: &Plan,
    table1: &Scene,
    on_part: &mut dyn FnMut(&str),
) -> Vec<ValidatedRun> {
    let strict = GpuOptions {
        validation: ValidationOptions::strict(),
        ..request.gpu.clone()
    };
    let dir = |part: &str| request.work.join("validated").join(part);
    let small = Plan {
        bench_counts: vec![p.check_blades],
        bench_frames: 2,
        bench_warmup: 1,
        width: p.check_size.0,
        height: p.check_size.1,
        msaa: p.msaa,
        shadow_map: p.shadow_map.min(2048),
        ..plan(true)
    };
    let mut runs = Vec::new();
    let mut run = |command: String, outcome: Outcome<ValidationCount>| {
        runs.push(ValidatedRun { command, outcome })
    };
    on_part("validated: bench");
    let validated = GpuReportRequest {
        gpu: strict.clone(),
        ..request.clone()
    };
    run(
        format!("bench --blades {} --frames 2", p.check_blades),
        Outcome::of(
            run_bench(
                &validated,
                &small,
                table1,
                vec![p.check_blades],
                &dir("bench"),
            )
            .map(|b| ValidationCount::of(&b.validation)),
        ),
    );
    on_part("validated: bench-grass");
    run(
        format!(
            "bench-grass --blades {} --colliders 0,16 --steps {}",
            p.check_blades, p.check_steps
        ),
        Outcome::of(
            bench_grass(
                table1,
                &[p.check_blades],
                &[0, 16],
                GrassSteps {
                    timed: p.check_steps,
                    warmup: 1,
                    wind_warmup: p.wind_warmup,
                },
                &strict,
                &mut |_| {},
            )
            .map(|b| ValidationCount::of(&b.validation)),
        ),
    );
    runs.extend(validated_wind_and_frames(
        request, p, table1, &strict, on_part,
    ));
    runs
}

/// `wind` (one-way and two-way) and `render` (`prairie`, `roll`) once
/// more, small, under `strict` validation.
fn validated_wind_and_frames(
    request: &GpuReportRequest,
    p: &Plan,
    table1: &Scene,
    strict: &GpuOptions,
    on_part: &mut dyn FnMut(&str),
) -> Vec<ValidatedRun> {
    let dir = |part: &str| request.work.join("validated").join(part);
    let mut runs = Vec::new();
    let mut run = |command: String, outcome: Outcome<ValidationCount>| {
        runs.push(ValidatedRun { command, outcome })
    };
    for (coupling, name) in [(Coupling::OneWay, "one-way"), (Coupling::TwoWay, "two-way")] {
        on_part(&format!("validated: wind --coupling {name}"));
        run(
            format!("wind --steps {} --coupling {name}", p.check_steps),
            Outcome::of(
                run_wind(
                    request,
                    table1,
                    coupling,
                    p.check_steps,
                    &dir(&format!("wind-{name}")),
                    strict,
                )
                .map(|w| ValidationCount::of(&w.validation)),
            ),
        );
    }
    for name in ["prairie", "roll"] {
        on_part(&format!("validated: render --scene {name}"));
        let blades = (name == "prairie").then_some(p.check_blades);
        run(
            format!(
                "render --scene {name}{} --frames 2 --width {} --height {}",
                blades.map_or(String::new(), |n| format!(" --blades {n}")),
                p.check_size.0,
                p.check_size.1
            ),
            Outcome::of(
                run_frames(
                    request,
                    name,
                    blades,
                    p.check_size,
                    p.msaa,
                    2,
                    &dir(&format!("render-{name}")),
                    strict,
                )
                .map(|(_, validation)| validation),
            ),
        );
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_names_its_report_in_plain_words() {
        assert_eq!(
            device_file_stem("NVIDIA H100 80GB HBM3"),
            "nvidia-h100-80gb-hbm3"
        );
        assert_eq!(
            device_file_stem("llvmpipe (LLVM 15.0.6, 256 bits)"),
            "llvmpipe"
        );
        assert_eq!(
            device_file_stem("AMD Radeon RX 7900 XTX (RADV NAVI31)"),
            "amd-radeon-rx-7900-xtx"
        );
        assert_eq!(device_file_stem("(?)"), "device");
    }
}
