//! `meadow bench`: the paper's Table 1 measured on this device. For each
//! blade count, with and without LOD, the `table1` scene runs warm-up
//! frames and then timed frames, each frame one simulation step (as in real
//! time) followed by the shadow pass, the colour pass and the read-back;
//! every phase is bracketed by GPU timestamps. Then the floor: the same
//! number of triangles drawn by a vertex+fragment pipeline. Writes
//! bench.json, bench.md (the paper's figures beside ours) and bench.svg.

use std::path::Path;
use std::time::Instant;

use crate::commands::{on_gpu, write_json};
use crate::error::{Error, Result};
use crate::frame::timing::{FrameTimings, Phase, Spread, TimingSummary};
use crate::frame::FrameRecorder;
use crate::gpu::query::PipelineStatistics;
use crate::gpu::{Gpu, GpuOptions, ValidationReport};
use crate::render::floor::{FloorPass, FloorShape};
use crate::render::{FrameUniforms, ViewMode};
use crate::report::files;
use crate::scene::{field, Scene, MAX_BLADES};

/// One row of the paper's Table 1 (GTX 670, 8x MSAA, 8192^2 shadow map).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PaperRow {
    pub blades: usize,
    pub wind_ms: f64,
    pub grass_ms: f64,
    pub render_ms_without_lod: f64,
    pub render_ms_with_lod: f64,
    pub fps_without_lod: f64,
    pub fps_with_lod: f64,
}

pub const PAPER_TABLE_1: [PaperRow; 4] = [
    PaperRow {
        blades: 50_000,
        wind_ms: 4.2,
        grass_ms: 8.5,
        render_ms_without_lod: 10.3,
        render_ms_with_lod: 8.3,
        fps_without_lod: 43.5,
        fps_with_lod: 47.5,
    },
    PaperRow {
        blades: 100_000,
        wind_ms: 4.2,
        grass_ms: 16.9,
        render_ms_without_lod: 15.8,
        render_ms_with_lod: 12.1,
        fps_without_lod: 27.1,
        fps_with_lod: 30.1,
    },
    PaperRow {
        blades: 150_000,
        wind_ms: 4.2,
        grass_ms: 25.8,
        render_ms_without_lod: 20.7,
        render_ms_with_lod: 15.0,
        fps_without_lod: 19.7,
        fps_with_lod: 22.2,
    },
    PaperRow {
        blades: 200_000,
        wind_ms: 4.2,
        grass_ms: 33.5,
        render_ms_without_lod: 25.2,
        render_ms_with_lod: 18.1,
        fps_without_lod: 15.9,
        fps_with_lod: 17.9,
    },
];

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
        crate::scene::check::render(&settings)
            .map_err(|e| Error::InvalidInput(format!("--{} {}", e.path, e.message)))?;
        self.scene.validate()?;
        self.scene.wind_grid()?;
        Ok(())
    }
}

/// The floor of one row: the grass's triangles without tessellation or
/// geometry shaders.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FloorResult {
    /// Quads per blade (the grass's triangles / 2 / blades, rounded).
    pub segments_per_blade: u32,
    pub triangles: u64,
    pub draw_ms: Spread,
    /// Grass draw median / floor draw median.
    pub grass_over_floor: f64,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchRow {
    pub blades: usize,
    pub lod: bool,
    pub frames: u32,
    pub warmup: u32,
    /// Per-phase GPU ms, wall-clock frame and FPS over the timed frames.
    pub timing: TimingSummary,
    /// Shadow + colour per frame (the paper's "render"), median and p95.
    pub render_ms: Option<Spread>,
    /// The grass draw's counters in the last timed frame.
    pub statistics: Option<PipelineStatistics>,
    /// Triangles the grass produced (geometry-shader primitives).
    pub triangles: Option<u64>,
    /// None with the reason in `floor_unavailable`.
    pub floor: Option<FloorResult>,
    pub floor_unavailable: Option<String>,
    /// The paper's row for this count, where it has one.
    pub paper: Option<PaperRow>,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct Bench {
    pub scene: String,
    pub device: String,
    pub device_type: String,
    pub driver: String,
    pub width: u32,
    pub height: u32,
    pub msaa_requested: u32,
    pub msaa_used: u32,
    pub shadow_map: u32,
    pub wind_grid: [u32; 3],
    pub jacobi_iterations: u32,
    pub rows: Vec<BenchRow>,
    pub paper_table_1: Vec<PaperRow>,
    pub validation: ValidationReport,
}

/// Runs the bench and writes DIR/bench.json, bench.md and bench.svg.
pub fn bench_to_dir(request: &BenchRequest, out: &Path) -> Result<Bench> {
    request.validate()?;
    files::ensure_dir(out)?;
    let ((rows, msaa_used, info), validation) = on_gpu(&request.gpu, |gpu| {
        let mut rows = Vec::new();
        let mut msaa_used = 0;
        for &count in &request.counts {
            for &lod in request.lod.settings() {
                let (row, used) = bench_row(gpu, request, count, lod)?;
                msaa_used = used;
                rows.push(row);
            }
        }
        Ok((rows, msaa_used, gpu.info().clone()))
    })?;
    let grid = request.scene.wind_grid()?;
    let bench = Bench {
        scene: request.scene.name.clone(),
        device: info.name,
        device_type: info.device_type,
        driver: info.driver,
        width: request.width,
        height: request.height,
        msaa_requested: request.msaa,
        msaa_used,
        shadow_map: request.scene.light.shadow_map,
        wind_grid: grid.cells.to_array(),
        jacobi_iterations: request.scene.wind.jacobi_iterations,
        rows,
        paper_table_1: PAPER_TABLE_1.to_vec(),
        validation,
    };
    write_json(&out.join("bench.json"), &bench)?;
    files::write_atomic(&out.join("bench.md"), markdown(&bench).as_bytes())?;
    files::write_atomic(&out.join("bench.svg"), svg(&bench).as_bytes())?;
    bench.validation.check()?;
    Ok(bench)
}

fn bench_row(
    gpu: &Gpu,
    request: &BenchRequest,
    count: usize,
    lod: bool,
) -> Result<(BenchRow, u32)> {
    let mut scene = request.scene.clone();
    scene.set_blade_count(count)?;
    scene.lod.enabled = lod;
    let (w, h) = (request.width, request.height);
    crate::frame::check_fits(gpu, &scene, w, h, request.msaa)?;
    let blades = field::generate(&scene.grass, scene.seed)?;
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
    let mut recorder =
        FrameRecorder::new(gpu, &scene, (w, h), request.msaa, &blades, Some(&dynamic))?;
    let (timings, wall, statistics) = run_frames(gpu, request, &scene, &mut recorder)?;
    let floor = floor(
        gpu,
        request,
        &scene,
        &recorder,
        &statistics,
        &timings,
        blades.len(),
    )?;
    let samples = recorder.samples();

    let timing = TimingSummary::of(&timings, &wall);
    let render: Option<Vec<f64>> = timings
        .iter()
        .map(|t| t.map(|t| t.shadow + t.color))
        .collect();
    let (floor, floor_unavailable) = match floor {
        Ok(f) => (Some(f), None),
        Err(why) => (None, Some(why)),
    };
    Ok((
        BenchRow {
            blades: count,
            lod,
            frames: request.frames,
            warmup: request.warmup,
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
        let frame = recorder.render(gpu, &uniforms, 1)?;
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
    let segments =
        ((stats.geometry_shader_primitives as f64 / (2.0 * blades as f64)).round() as u32).max(1);
    let blade_vertices = recorder.blades().buffer();
    let Some(mut pass) = FloorPass::new(gpu, recorder.renderer().formats(), blade_vertices)? else {
        return Ok(Err("no timestamps on this device".into()));
    };
    let uniforms = FrameUniforms::new(scene, request.width, request.height, ViewMode::Shaded, 0.0);
    let times = pass.time(
        recorder.commands(),
        recorder.renderer().targets(),
        blade_vertices,
        &uniforms,
        FloorShape {
            blades: blades as u32,
            segments,
        },
        request.frames,
    );
    let draw_ms = Spread::of(&times?).expect("at least one frame");
    Ok(Ok(FloorResult {
        segments_per_blade: segments,
        triangles: 2 * segments as u64 * blades as u64,
        draw_ms,
        grass_over_floor: grass_draw.median / draw_ms.median,
    }))
}

fn ms(s: Option<Spread>) -> String {
    s.map(|s| format!("{:.2}", s.median))
        .unwrap_or_else(|| "n/a".into())
}

/// bench.md: the paper's Table 1 columns, ours beside the paper's, then
/// what the paper lacks.
pub fn markdown(b: &Bench) -> String {
    let mut md = String::new();
    md += &format!(
        "# meadow bench: {} on {}\n\n\
         Device: {} ({}), driver {}. {}x{}, MSAA {}x used ({}x asked), shadow map {}, \
         wind grid {}x{}x{} with {} Jacobi iterations. Each row: {} warm-up frames, then {} \
         timed frames of one simulation step each; GPU times are medians of timestamp \
         queries (p95 in bench.json); FPS (wall) is 1000 / the median wall-clock frame \
         (simulation, render and read-back, not PNG encoding).\n\n",
        b.scene,
        b.device,
        b.device,
        b.device_type,
        b.driver,
        b.width,
        b.height,
        b.msaa_used,
        b.msaa_requested,
        b.shadow_map,
        b.wind_grid[0],
        b.wind_grid[1],
        b.wind_grid[2],
        b.jacobi_iterations,
        b.rows.first().map_or(0, |r| r.warmup),
        b.rows.first().map_or(0, |r| r.frames),
    );
    md += "## Table 1, ours beside the paper's (GTX 670, C++/OpenGL)\n\n";
    md += "| blades | LOD | wind ms | paper | grass ms | paper | render ms (shadow + colour) | paper | FPS (GPU frame) | FPS (wall) | paper FPS |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &b.rows {
        let g = r.timing.gpu_ms;
        let paper = |f: fn(&PaperRow) -> f64| {
            r.paper
                .as_ref()
                .map(|p| format!("{:.1}", f(p)))
                .unwrap_or_else(|| "-".into())
        };
        let (paper_render, paper_fps) = if r.lod {
            (paper(|p| p.render_ms_with_lod), paper(|p| p.fps_with_lod))
        } else {
            (
                paper(|p| p.render_ms_without_lod),
                paper(|p| p.fps_without_lod),
            )
        };
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.blades,
            if r.lod { "on" } else { "off" },
            ms(g.map(|g| g.wind)),
            paper(|p| p.wind_ms),
            ms(g.map(|g| g.grass)),
            paper(|p| p.grass_ms),
            ms(r.render_ms),
            paper_render,
            g.map(|g| format!("{:.2}", 1000.0 / g.frame.median))
                .unwrap_or_else(|| "n/a".into()),
            r.timing
                .fps
                .map(|f| format!("{f:.2}"))
                .unwrap_or_else(|| "n/a".into()),
            paper_fps,
        );
    }
    md += "\n## What the paper does not give\n\n";
    md += "| blades | LOD | shadow ms | colour ms | grass draw ms | readback ms | GPU frame ms | triangles | floor ms | grass / floor |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &b.rows {
        let g = r.timing.gpu_ms;
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.blades,
            if r.lod { "on" } else { "off" },
            ms(g.map(|g| g.shadow)),
            ms(g.map(|g| g.color)),
            ms(g.map(|g| g.grass_draw)),
            ms(g.map(|g| g.readback)),
            ms(g.map(|g| g.frame)),
            r.triangles
                .map(|t| t.to_string())
                .unwrap_or_else(|| "n/a".into()),
            ms(r.floor.as_ref().map(|f| f.draw_ms)),
            r.floor
                .as_ref()
                .map(|f| format!("{:.2}x", f.grass_over_floor))
                .unwrap_or_else(|| r.floor_unavailable.clone().unwrap_or_else(|| "n/a".into())),
        );
    }
    if b.rows.iter().any(|r| r.timing.gpu_ms.is_none()) {
        md += &format!(
            "\nGPU times unavailable: {}.\n",
            b.rows
                .iter()
                .find_map(|r| r.timing.gpu_unavailable.clone())
                .unwrap_or_default()
        );
    }
    md += "\nThe floor draws the grass's triangle count (its geometry-shader primitives) as \
           straight quads along each blade's curve with a vertex and a fragment shader only, \
           at the same resolution and MSAA; grass / floor is the grass draw's median over the \
           floor's. lavapipe's \"GPU\" times are CPU clock readings of its own work.\n";
    md
}

/// bench.svg: ms per frame against blade count (log scale), one line per
/// phase, ours solid (LOD on dark, off light) and the paper's dashed.
/// Written by hand: a few dozen elements; a plotting crate would need a
/// font back end to lay out its labels.
pub fn svg(b: &Bench) -> String {
    let (width, height) = (860.0, 520.0);
    let (left, right, top, bottom) = (70.0, 210.0, 40.0, 60.0);
    let plot_w = width - left - right;
    let plot_h = height - top - bottom;

    // Series: (label, color, dashed, opacity, points).
    type Series = (String, &'static str, bool, f64, Vec<(f64, f64)>);
    let mut series: Vec<Series> = Vec::new();
    let phases = [
        (Phase::Wind, "#1f77b4"),
        (Phase::Grass, "#2ca02c"),
        (Phase::Shadow, "#7f7f7f"),
        (Phase::Color, "#ff7f0e"),
        (Phase::Frame, "#d62728"),
    ];
    for lod in [true, false] {
        let rows: Vec<&BenchRow> = b.rows.iter().filter(|r| r.lod == lod).collect();
        if rows.is_empty() {
            continue;
        }
        for (phase, color) in phases {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter_map(|r| {
                    r.timing
                        .gpu_ms
                        .map(|g| (r.blades as f64, g.get(phase).median))
                })
                .collect();
            if !points.is_empty() {
                series.push((
                    format!(
                        "ours {} (LOD {})",
                        phase.name(),
                        if lod { "on" } else { "off" }
                    ),
                    color,
                    false,
                    if lod { 1.0 } else { 0.45 },
                    points,
                ));
            }
        }
    }
    let paper = |f: fn(&PaperRow) -> f64| -> Vec<(f64, f64)> {
        PAPER_TABLE_1
            .iter()
            .map(|p| (p.blades as f64, f(p)))
            .collect()
    };
    series.push((
        "paper wind".into(),
        "#1f77b4",
        true,
        1.0,
        paper(|p| p.wind_ms),
    ));
    series.push((
        "paper grass".into(),
        "#2ca02c",
        true,
        1.0,
        paper(|p| p.grass_ms),
    ));
    series.push((
        "paper render (LOD on)".into(),
        "#ff7f0e",
        true,
        1.0,
        paper(|p| p.render_ms_with_lod),
    ));
    series.push((
        "paper render (LOD off)".into(),
        "#ff7f0e",
        true,
        0.45,
        paper(|p| p.render_ms_without_lod),
    ));

    let all = series.iter().flat_map(|s| s.4.iter());
    let (mut x_max, mut y_min, mut y_max) = (1.0f64, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x_max = x_max.max(x);
        if y > 0.0 {
            y_min = y_min.min(y);
            y_max = y_max.max(y);
        }
    }
    let lo = y_min.log10().floor();
    let hi = y_max.log10().ceil().max(lo + 1.0);
    let sx = |x: f64| left + x / x_max * plot_w;
    let sy = |y: f64| top + plot_h - (y.max(10f64.powf(lo)).log10() - lo) / (hi - lo) * plot_h;

    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"{width}\" height=\"{height}\" fill=\"white\"/>\n\
         <text x=\"{left}\" y=\"24\" font-size=\"15\">{}: GPU ms per frame phase against blade count (log scale)</text>\n",
        xml_escape(&b.device)
    );
    let mut decade = lo;
    while decade <= hi {
        let y = sy(10f64.powf(decade));
        out += &format!(
            "<line x1=\"{left}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#ddd\"/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>\n",
            left + plot_w,
            left - 6.0,
            y + 4.0,
            10f64.powf(decade)
        );
        decade += 1.0;
    }
    let mut counts: Vec<usize> = b.rows.iter().map(|r| r.blades).collect();
    counts.extend(PAPER_TABLE_1.iter().map(|p| p.blades));
    counts.sort_unstable();
    counts.dedup();
    for c in counts {
        let x = sx(c as f64);
        out += &format!(
            "<line x1=\"{x:.1}\" y1=\"{top}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#eee\"/>\n\
             <text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>\n",
            top + plot_h,
            top + plot_h + 16.0,
            if c >= 1000 {
                format!("{}K", c / 1000)
            } else {
                c.to_string()
            }
        );
    }
    out += &format!(
        "<rect x=\"{left}\" y=\"{top}\" width=\"{plot_w}\" height=\"{plot_h}\" fill=\"none\" stroke=\"#333\"/>\n\
         <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">blades</text>\n\
         <text x=\"16\" y=\"{:.1}\" transform=\"rotate(-90 16 {:.1})\" text-anchor=\"middle\">ms</text>\n",
        left + plot_w / 2.0,
        height - 18.0,
        top + plot_h / 2.0,
        top + plot_h / 2.0
    );
    for (i, (label, color, dashed, opacity, points)) in series.iter().enumerate() {
        let path: Vec<String> = points
            .iter()
            .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
            .collect();
        let dash = if *dashed {
            " stroke-dasharray=\"6 4\""
        } else {
            ""
        };
        out += &format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"2\" stroke-opacity=\"{opacity}\"{dash}/>\n",
            path.join(" ")
        );
        let ly = top + 10.0 + i as f64 * 18.0;
        let lx = left + plot_w + 12.0;
        out += &format!(
            "<line x1=\"{lx:.1}\" y1=\"{ly:.1}\" x2=\"{:.1}\" y2=\"{ly:.1}\" stroke=\"{color}\" stroke-width=\"2\" stroke-opacity=\"{opacity}\"{dash}/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\">{}</text>\n",
            lx + 24.0,
            lx + 30.0,
            ly + 4.0,
            xml_escape(label)
        );
    }
    out += "</svg>\n";
    out
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
