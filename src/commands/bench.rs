//! `meadow bench`: the paper's Table 1 measured on this device. For each
//! blade count, with and without LOD, and each without and with culling,
//! the `table1` scene runs warm-up frames and then timed frames, each frame
//! one simulation step (as in real time) followed by the cull pass (when
//! on), the shadow pass, the colour pass and the read-back; every phase is
//! bracketed by GPU timestamps. Then, on the rows without culling, the
//! floor: the same number of triangles drawn by a vertex+fragment pipeline. Writes
//! bench.json, bench.md (the paper's figures beside ours) and bench.svg.

use std::path::Path;
use std::time::Instant;

use crate::commands::on_gpu;
use crate::error::{Error, Result};
use crate::frame::timing::{FrameTimings, Phase, Spread, TimingSummary};
use crate::frame::FrameRecorder;
use crate::gpu::query::PipelineStatistics;
use crate::gpu::{Gpu, GpuOptions};
use crate::render::floor::{FloorPass, FloorShape};
use crate::render::{FrameUniforms, ViewMode};
pub use crate::report::bench::{
    markdown, svg, Bench, BenchRow, FloorResult, PaperRow, PAPER_TABLE_1,
};
use crate::report::claim::OutputClaim;
use crate::report::files;
use crate::scene::{field, Scene, MAX_BLADES};

pub mod against;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LodChoice {
    Both,
    On,
    Off,
}

impl LodChoice {
    pub fn settings(self) -> &'static [bool] {
        match self {
            LodChoice::Both => &[false, true],
            LodChoice::On => &[true],
            LodChoice::Off => &[false],
        }
    }
}

#[derive(Clone, Debug)]
pub struct BenchRequest {
    pub scene: Scene,
    pub counts: Vec<usize>,
    pub lod: LodChoice,
    pub frames: u32,
    pub warmup: u32,
    pub width: u32,
    pub height: u32,
    pub msaa: u32,
    /// Each row run again on the scene's ground made flat (the same
    /// blades): what the terrain costs.
    pub also_flat: bool,
    pub gpu: GpuOptions,
}

pub const MAX_BENCH_FRAMES: u32 = 10_000;

impl BenchRequest {
    pub fn validate(&self) -> Result<()> {
        if self.counts.is_empty() || self.counts.iter().any(|&n| n == 0 || n > MAX_BLADES) {
            return Err(Error::InvalidInput(format!(
                "--blades {:?} is not allowed, use counts in 1..={MAX_BLADES}",
                self.counts
            )));
        }
        if !(1..=MAX_BENCH_FRAMES).contains(&self.frames) || self.warmup > MAX_BENCH_FRAMES {
            return Err(Error::InvalidInput(format!(
                "--frames {} / --warmup {} are not allowed, use 1..={MAX_BENCH_FRAMES} and 0..={MAX_BENCH_FRAMES}",
                self.frames, self.warmup
            )));
        }
        let settings = crate::scene::RenderSettings {
            width: self.width,
            height: self.height,
            msaa: self.msaa,
            ..self.scene.render.clone()
        };
        settings
            .check()
            .map_err(|e| Error::InvalidInput(format!("--{} {}", e.path, e.message)))?;
        self.scene.validate()?;
        self.scene.wind_grid()?;
        if self.also_flat && self.scene.ground.terrain().is_flat() {
            return Err(Error::InvalidInput(format!(
                "--also-flat compares the scene's terrain with flat ground, but {}'s ground is flat; use a scene with [[ground.hill]], [[ground.ridge]] or a height_map (hills)",
                self.scene.name
            )));
        }
        Ok(())
    }
}

/// What a `bench` run is about to do, for a progress display.
#[derive(Clone, Copy, Debug)]
pub enum BenchStep {
    /// The wind step alone with each pressure solver.
    Solvers,
    /// A row: blades, LOD, culling, the scene's terrain or flat ground.
    Row {
        blades: usize,
        lod: bool,
        cull: bool,
        terrain: bool,
    },
}

/// Where a `bench` run is: steps done and in all, and the next one.
#[derive(Clone, Copy, Debug)]
pub struct BenchProgress {
    pub done: usize,
    pub total: usize,
    pub next: BenchStep,
}

/// Runs the bench and writes DIR/bench.json, bench.md and bench.svg,
/// replacing only an earlier run's (`overwrite`: any file of those names;
/// `report::claim`); `on_step` hears of each step (the solvers, then each
/// row) before it starts.
pub fn bench_to_dir(
    request: &BenchRequest,
    out: &Path,
    overwrite: bool,
    on_step: &mut dyn FnMut(BenchProgress),
) -> Result<Bench> {
    request.validate()?;
    files::ensure_dir(out)?;
    let planned = ["bench.json", "bench.md", "bench.svg"].map(String::from);
    let claim = OutputClaim::new(out, &planned, overwrite)?;
    let grounds: &[bool] = if request.also_flat {
        &[true, false]
    } else {
        &[true]
    };
    let total = 1 + request.counts.len() * request.lod.settings().len() * 2 * grounds.len();
    let ((rows, wind_solvers, msaa_used, info, device_memory), validation) =
        on_gpu(&request.gpu, |gpu| {
            on_step(BenchProgress {
                done: 0,
                total,
                next: BenchStep::Solvers,
            });
            let wind_solvers = crate::commands::wind::compare_solvers(
                gpu,
                &request.scene,
                request.frames,
                &mut |_| {},
            )?;
            let (rows, msaa_used) = bench_rows(gpu, request, grounds, total, on_step)?;
            Ok((
                rows,
                wind_solvers,
                msaa_used,
                gpu.info().clone(),
                gpu.device_memory(),
            ))
        })?;
    let grid = request.scene.wind_grid()?;
    let bench = Bench {
        scene: request.scene.name.clone(),
        device: info.name,
        device_type: info.device_type,
        driver: info.driver,
        device_memory,
        width: request.width,
        height: request.height,
        msaa_requested: request.msaa,
        msaa_used,
        shadow_map: request.scene.light.shadow_map,
        wind_grid: grid.cells.to_array(),
        wind_solver: request.scene.wind.solver,
        jacobi_iterations: request.scene.wind.jacobi_iterations,
        v_cycles: request.scene.wind.v_cycles,
        wind_solvers,
        rows,
        paper_table_1: PAPER_TABLE_1.to_vec(),
        validation,
    };
    claim.begin()?;
    claim.write_json("bench.json", &bench)?;
    claim.write("bench.md", markdown(&bench).as_bytes())?;
    claim.write("bench.svg", svg(&bench)?.as_bytes())?;
    bench.validation.check()?;
    Ok(bench)
}

/// Each row of the bench: every count, LOD setting, culling off and on,
/// and ground (`grounds`: the scene's own, and flat where asked), each
/// told to `on_step` (of `total` steps, the solvers' first) before it
/// runs; and the MSAA count the rows used.
fn bench_rows(
    gpu: &Gpu,
    request: &BenchRequest,
    grounds: &[bool],
    total: usize,
    on_step: &mut dyn FnMut(BenchProgress),
) -> Result<(Vec<BenchRow>, u32)> {
    let mut rows = Vec::new();
    let mut msaa_used = 0;
    for &count in &request.counts {
        for &lod in request.lod.settings() {
            for cull in [false, true] {
                for &terrain in grounds {
                    on_step(BenchProgress {
                        done: 1 + rows.len(),
                        total,
                        next: BenchStep::Row {
                            blades: count,
                            lod,
                            cull,
                            terrain,
                        },
                    });
                    let (row, used) = bench_row(gpu, request, count, lod, cull, terrain)?;
                    msaa_used = used;
                    rows.push(row);
                }
            }
        }
    }
    Ok((rows, msaa_used))
}

fn bench_row(
    gpu: &Gpu,
    request: &BenchRequest,
    count: usize,
    lod: bool,
    cull: bool,
    terrain: bool,
) -> Result<(BenchRow, u32)> {
    let mut scene = request.scene.clone();
    if !terrain {
        scene.ground = scene.ground.flattened();
    }
    scene.set_blade_count(count)?;
    scene.lod.enabled = lod;
    scene.cull.enabled = cull;
    let (w, h) = (request.width, request.height);
    crate::frame::check_fits(gpu, &scene, w, h, request.msaa)?;
    let blades = scene.field()?;
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
    let mut recorder =
        FrameRecorder::new(gpu, &scene, (w, h), request.msaa, &blades, Some(&dynamic))?;
    let (timings, wall, statistics) = run_frames(gpu, request, &scene, &mut recorder)?;
    let cull_counts = recorder.cull().map(|c| c.counts());
    // The floor draws every blade: it stands beside the uncull draw.
    let floor = if cull {
        Err("measured on the row without culling".to_string())
    } else {
        floor(
            gpu,
            request,
            &scene,
            &recorder,
            &statistics,
            &timings,
            blades.len(),
        )?
    };
    let samples = recorder.samples();

    let timing = TimingSummary::of(&timings, &wall, &recorder.untimed_phases());
    let render: Option<Vec<f64>> = timings
        .iter()
        .map(|t| t.map(|t| t.cull + t.shadow + t.color))
        .collect();
    let (floor, floor_unavailable) = match floor {
        Ok(f) => (Some(f), None),
        Err(why) => (None, Some(why)),
    };
    Ok((
        BenchRow {
            blades: count,
            lod,
            cull,
            terrain: !scene.ground.terrain().is_flat(),
            cull_counts,
            frames: request.frames,
            warmup: request.warmup,
            overlap: recorder.overlap(),
            timing,
            render_ms: render.and_then(|r| Spread::of(&r)),
            statistics,
            triangles: statistics.map(|s| s.geometry_shader_primitives),
            floor,
            floor_unavailable,
            paper: PAPER_TABLE_1.iter().find(|r| r.blades == count).copied(),
        },
        samples,
    ))
}

type Timed = (
    Vec<Option<FrameTimings>>,
    Vec<f64>,
    Option<PipelineStatistics>,
);

/// Warm-up frames, then the timed ones: each one simulation step, then
/// shadow, colour and read-back.
fn run_frames(
    gpu: &Gpu,
    request: &BenchRequest,
    scene: &Scene,
    recorder: &mut FrameRecorder,
) -> Result<Timed> {
    let simulation = recorder.simulation().expect("made with dynamics");
    let dt = simulation.dt();
    let mut steps_done = simulation.steps_done();
    let mut timings = Vec::new();
    let mut wall = Vec::new();
    let mut statistics = None;
    for f in 0..request.warmup + request.frames {
        steps_done += 1;
        let time = steps_done as f32 * dt;
        let uniforms =
            FrameUniforms::new(scene, request.width, request.height, ViewMode::Shaded, time);
        let started = Instant::now();
        // The next frame's step goes beside this frame's drawing where the
        // recorder overlaps them (`render.overlap`).
        let next = u64::from(f + 1 < request.warmup + request.frames);
        let frame = recorder.render_then(gpu, &uniforms, 1, next)?;
        if f >= request.warmup {
            wall.push(started.elapsed().as_secs_f64() * 1e3);
            timings.push(frame.timings);
            statistics = frame.statistics;
        }
    }
    Ok((timings, wall, statistics))
}

/// The floor for this row, or why there is none.
fn floor(
    gpu: &Gpu,
    request: &BenchRequest,
    scene: &Scene,
    recorder: &FrameRecorder,
    statistics: &Option<PipelineStatistics>,
    timings: &[Option<FrameTimings>],
    blades: usize,
) -> Result<std::result::Result<FloorResult, String>> {
    let Some(stats) = statistics else {
        return Ok(Err(
            "no pipeline statistics on this device: the grass's triangle count is unknown".into(),
        ));
    };
    let grass_draw: Option<Vec<f64>> = timings.iter().map(|t| t.map(|t| t.grass_draw)).collect();
    let Some(grass_draw) = grass_draw.and_then(|g| Spread::of(&g)) else {
        return Ok(Err("no timestamps on this device".into()));
    };
    if let Some((_, why)) = recorder
        .untimed_phases()
        .into_iter()
        .find(|(p, _)| *p == Phase::GrassDraw)
    {
        return Ok(Err(format!("the grass draw cannot be timed here: {why}")));
    }
    let segments = FloorShape::segments_of(stats.geometry_shader_primitives, blades as u64);
    let blade_vertices = recorder.blades().buffer();
    let range = gpu.limits().max_storage_buffer_range as u64;
    if blade_vertices.size > range {
        return Ok(Err(format!(
            "the floor reads every control point through one binding, and {blades} blades' are more than this device's maxStorageBufferRange ({} MiB)",
            range >> 20
        )));
    }
    let Some(mut pass) = FloorPass::new(gpu, recorder.renderer().formats(), blade_vertices)? else {
        return Ok(Err("no timestamps on this device".into()));
    };
    let uniforms = FrameUniforms::new(scene, request.width, request.height, ViewMode::Shaded, 0.0);
    let shape = FloorShape {
        blades: blades as u32,
        segments,
    };
    let times = pass.time(
        recorder.commands(),
        recorder.renderer().targets(),
        blade_vertices,
        &uniforms,
        shape,
        request.frames,
    );
    let draw_ms = Spread::of(&times?).expect("at least one frame");
    Ok(Ok(FloorResult {
        segments_per_blade: segments,
        triangles: shape.triangles(),
        draw_ms,
        grass_over_floor: grass_draw.median / draw_ms.median,
    }))
}
