//! What `meadow bench` measured and how it is written: the paper's Table 1,
//! the rows of the bench (the data of bench.json), and bench.md and
//! bench.svg made from them.

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::frame::timing::{Phase, Spread, TimingSummary};
use crate::frame::CullCounts;
use crate::gpu::query::PipelineStatistics;
use crate::gpu::{DeviceMemory, ValidationReport};
use crate::model::wind::PressureSolver;
use crate::report::wind::SolverTiming;

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
    /// Whether the cull pass ran, and of the last frame's blades how many
    /// each pass drew (null without culling: all of them).
    pub cull: bool,
    /// Whether the ground had the scene's terrain (false: flat, as the
    /// scene's, or made flat by `--also-flat`).
    pub terrain: bool,
    pub cull_counts: Option<CullCounts>,
    pub frames: u32,
    pub warmup: u32,
    /// Where each frame's steps ran: "off" (steps, then the drawing, in
    /// one submission), "one queue" or "two queues" (beside the drawing of
    /// the frame before, in a submission of their own, on the main queue
    /// or on one beside it: `render.overlap`). Beside the drawing the
    /// frame's GPU time is its drawing's; the wind and grass times are the
    /// steps' own.
    pub overlap: &'static str,
    /// Per-phase GPU ms, wall-clock frame and FPS over the timed frames.
    pub timing: TimingSummary,
    /// Cull + shadow + colour per frame (the paper's "render", with the
    /// cull pass that decides what it draws), median and p95.
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
    /// The device memory the run's allocations held at its end and at
    /// most (the largest row's).
    pub device_memory: DeviceMemory,
    pub width: u32,
    pub height: u32,
    pub msaa_requested: u32,
    pub msaa_used: u32,
    pub shadow_map: u32,
    pub wind_grid: [u32; 3],
    /// The scene's pressure solver, which the rows use.
    pub wind_solver: PressureSolver,
    pub jacobi_iterations: u32,
    pub v_cycles: u32,
    /// The scene's wind step with each pressure solver, over as many steps
    /// as a row has timed frames (the rows use the scene's solver).
    pub wind_solvers: Vec<SolverTiming>,
    pub rows: Vec<BenchRow>,
    pub paper_table_1: Vec<PaperRow>,
    pub validation: ValidationReport,
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
         wind grid {}x{}x{} solved by {}. Each row: {} warm-up frames, then {} \
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
        crate::report::wind::describe(b.wind_solver, b.jacobi_iterations, b.v_cycles),
        b.rows.first().map_or(0, |r| r.warmup),
        b.rows.first().map_or(0, |r| r.frames),
    );
    if let Some(r) = b.rows.first().filter(|r| r.overlap != "off") {
        md += &format!(
            "Each frame's step ran beside the drawing of the frame before ({};              render.overlap): a frame's GPU time is its drawing's, and the wind and grass              columns are the steps' own.

",
            r.overlap
        );
    }
    md += &table1_markdown(b);
    md += &culling_markdown(b);
    md += &terrain_markdown(b);
    md += "\n## The wind's pressure solvers\n\n\
           The wind step alone, with each solver (the paper's is Jacobi), and the share of \
           the divergence its projection leaves on the last step:\n\n";
    md += &crate::report::wind::markdown(&b.wind_solvers);
    md += &beyond_the_paper_markdown(b);
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

/// bench.md's Table 1: ours beside the paper's, row by row.
fn table1_markdown(b: &Bench) -> String {
    let mut md = String::new();
    md += "## Table 1, ours beside the paper's (GTX 670, C++/OpenGL)\n\n";
    md += "| blades | LOD | culling | wind ms | paper | grass ms | paper | render ms (cull + shadow + colour) | paper | FPS (GPU frame) | FPS (wall) | paper FPS |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
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
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            blades_cell(b, r),
            if r.lod { "on" } else { "off" },
            if r.cull { "on" } else { "off" },
            ms(g.and_then(|g| g.wind)),
            paper(|p| p.wind_ms),
            ms(g.and_then(|g| g.grass)),
            paper(|p| p.grass_ms),
            ms(r.render_ms),
            paper_render,
            g.and_then(|g| g.frame)
                .map(|f| format!("{:.2}", 1000.0 / f.median))
                .unwrap_or_else(|| "n/a".into()),
            r.timing
                .fps
                .map(|f| format!("{f:.2}"))
                .unwrap_or_else(|| "n/a".into()),
            paper_fps,
        );
    }
    md
}

/// bench.md's figures the paper does not give: each phase, the triangles
/// and the vertex-and-fragment floor, row by row.
fn beyond_the_paper_markdown(b: &Bench) -> String {
    let mut md = String::new();
    md += "\n## What the paper does not give\n\n";
    md += "| blades | LOD | culling | cull ms | shadow ms | colour ms | grass draw ms | readback ms | GPU frame ms | triangles | floor ms | grass / floor |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &b.rows {
        let g = r.timing.gpu_ms;
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            blades_cell(b, r),
            if r.lod { "on" } else { "off" },
            if r.cull { "on" } else { "off" },
            ms(g.and_then(|g| g.cull).filter(|_| r.cull)),
            ms(g.and_then(|g| g.shadow)),
            ms(g.and_then(|g| g.color)),
            ms(g.and_then(|g| g.grass_draw)),
            ms(g.and_then(|g| g.readback)),
            ms(g.and_then(|g| g.frame)),
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
    md
}

/// A row's blade count, marked where the run has rows on the scene's
/// terrain and this one is on flat ground.
fn blades_cell(b: &Bench, r: &BenchRow) -> String {
    if !r.terrain && b.rows.iter().any(|r| r.terrain) {
        format!("{} (flat ground)", r.blades)
    } else {
        r.blades.to_string()
    }
}

/// The terrain table (with `--also-flat`): each row on the scene's terrain
/// beside its twin on flat ground, the same blades, as ratios of the same
/// run.
fn terrain_markdown(b: &Bench) -> String {
    let pairs: Vec<(&BenchRow, &BenchRow)> = b
        .rows
        .iter()
        .filter(|r| r.terrain)
        .filter_map(|t| {
            b.rows
                .iter()
                .find(|f| !f.terrain && (f.blades, f.lod, f.cull) == (t.blades, t.lod, t.cull))
                .map(|f| (t, f))
        })
        .collect();
    if pairs.is_empty() {
        return String::new();
    }
    let mut md = "\n## Terrain against flat ground in this run\n\n\
         The same rows on the scene's ground made flat (the same blades, rooted at y = 0); \
         GPU ms medians, flat / terrain / terrain over flat.\n\n\
         | blades | LOD | culling | wind | | | grass | | | cull | | | shadow | | | colour | | | GPU frame | | |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
        .to_string();
    // Wind, grass, cull (where it ran), shadow, colour and the GPU frame,
    // medians.
    let medians = |r: &BenchRow| {
        r.timing.gpu_ms.map_or([None; 6], |g| {
            let cull = g.cull.filter(|_| r.cull);
            [g.wind, g.grass, cull, g.shadow, g.color, g.frame].map(|s| s.map(|s| s.median))
        })
    };
    for (t, f) in pairs {
        let mut cells = Vec::new();
        for (flat, terrain) in medians(f).into_iter().zip(medians(t)) {
            cells.push(flat.map_or("n/a".into(), |v| format!("{v:.2}")));
            cells.push(terrain.map_or("n/a".into(), |v| format!("{v:.2}")));
            cells.push(match (flat, terrain) {
                (Some(a), Some(b)) if a > 0.0 => format!("{:.2}x", b / a),
                _ => "n/a".into(),
            });
        }
        md += &format!(
            "| {} | {} | {} | {} |\n",
            t.blades,
            if t.lod { "on" } else { "off" },
            if t.cull { "on" } else { "off" },
            cells.join(" | ")
        );
    }
    md
}

/// The culling table: for each blade count and LOD, what the cull pass
/// kept and the render and GPU frame without and with it, as ratios of
/// the same run.
fn culling_markdown(b: &Bench) -> String {
    let mut md = "\n## Culling, off and on in this run\n\n\
         | blades | LOD | left by distance | not edge-on | occluded | in view | shadow casters | render ms off | on | off / on | GPU frame ms off | on | off / on |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
        .to_string();
    let frame = |r: &BenchRow| r.timing.gpu_ms.and_then(|g| g.frame).map(|s| s.median);
    let render = |r: &BenchRow| r.render_ms.map(|s| s.median);
    let ratio = |off: Option<f64>, on: Option<f64>| match (off, on) {
        (Some(off), Some(on)) if on > 0.0 => format!("{:.2}x", off / on),
        _ => "n/a".into(),
    };
    for on in b.rows.iter().filter(|r| r.cull) {
        let Some(off) = b.rows.iter().find(|r| {
            !r.cull && r.blades == on.blades && r.lod == on.lod && r.terrain == on.terrain
        }) else {
            continue;
        };
        let share = |n: u32, of: u32| format!("{n} ({:.0}%)", 100.0 * n as f64 / of.max(1) as f64);
        let [kept, facing, occluded, in_view, casters] = on.cull_counts.map_or(
            [
                "n/a".to_string(),
                "n/a".into(),
                "n/a".into(),
                "n/a".into(),
                "n/a".into(),
            ],
            |c| {
                [
                    c.thinned_to,
                    c.face_camera,
                    c.occluded,
                    c.in_view,
                    c.shadow_casters,
                ]
                .map(|n| share(n, c.blades))
            },
        );
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            blades_cell(b, on),
            if on.lod { "on" } else { "off" },
            kept,
            facing,
            occluded,
            in_view,
            casters,
            ms(off.render_ms),
            ms(on.render_ms),
            ratio(render(off), render(on)),
            ms(off.timing.gpu_ms.and_then(|g| g.frame)),
            ms(on.timing.gpu_ms.and_then(|g| g.frame)),
            ratio(frame(off), frame(on)),
        );
    }
    md
}

/// One line of bench.svg: its label, colour, whether it is the paper's,
/// its opacity and its points (blades, ms).
type Series = (String, RGBColor, bool, f64, Vec<(f64, f64)>);

/// The lines of bench.svg: ours for each phase with LOD on and off (the
/// run's default pipeline: culling where it has it, the scene's own
/// ground), then the paper's.
fn plotted_series(b: &Bench) -> Vec<Series> {
    let mut series: Vec<Series> = Vec::new();
    let phases = [
        (Phase::Wind, RGBColor(0x1f, 0x77, 0xb4)),
        (Phase::Grass, RGBColor(0x2c, 0xa0, 0x2c)),
        (Phase::Shadow, RGBColor(0x7f, 0x7f, 0x7f)),
        (Phase::Color, RGBColor(0xff, 0x7f, 0x0e)),
        (Phase::Frame, RGBColor(0xd6, 0x27, 0x28)),
    ];
    // The scene's own ground where the run also has it made flat.
    let terrain = b.rows.iter().any(|r| r.terrain);
    for lod in [true, false] {
        // The default pipeline: culling on where the run has it.
        let culled = b.rows.iter().any(|r| r.cull);
        let rows: Vec<&BenchRow> = b
            .rows
            .iter()
            .filter(|r| r.lod == lod && r.cull == culled && r.terrain == terrain)
            .collect();
        for (phase, color) in phases {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter_map(|r| {
                    r.timing
                        .gpu_ms
                        .and_then(|g| g.get(phase))
                        .map(|s| (r.blades as f64, s.median))
                })
                .collect();
            if !points.is_empty() {
                let lod = if lod { "on" } else { "off" };
                let opacity = if lod == "on" { 1.0 } else { 0.45 };
                let label = format!("ours {} (LOD {lod})", phase.name());
                series.push((label, color, false, opacity, points));
            }
        }
    }
    let paper = |f: fn(&PaperRow) -> f64| -> Vec<(f64, f64)> {
        PAPER_TABLE_1
            .iter()
            .map(|p| (p.blades as f64, f(p)))
            .collect()
    };
    let (wind, grass, render) = (phases[0].1, phases[1].1, phases[3].1);
    series.push(("paper wind".into(), wind, true, 1.0, paper(|p| p.wind_ms)));
    series.push((
        "paper grass".into(),
        grass,
        true,
        1.0,
        paper(|p| p.grass_ms),
    ));
    let with_lod = paper(|p| p.render_ms_with_lod);
    series.push(("paper render (LOD on)".into(), render, true, 1.0, with_lod));
    let without_lod = paper(|p| p.render_ms_without_lod);
    series.push((
        "paper render (LOD off)".into(),
        render,
        true,
        0.45,
        without_lod,
    ));
    series
}

/// bench.svg: GPU ms per frame phase against blade count (both axes log
/// scale, so small and large counts read alike), one line per phase, ours (LOD on dark, off light) and the paper's (with a
/// dot at each of its counts), drawn with plotters.
pub fn svg(b: &Bench) -> Result<String> {
    let series = plotted_series(b);
    let points = || series.iter().flat_map(|s| s.4.iter().copied());
    let x_min = points().map(|p| p.0).fold(f64::MAX, f64::min).max(1.0);
    let x_max = points().map(|p| p.0).fold(1.0, f64::max);
    let positive = || points().map(|p| p.1).filter(|&y| y > 0.0);
    let y_min = positive().fold(f64::MAX, f64::min).min(1.0);
    let y_max = positive().fold(f64::MIN, f64::max).max(y_min * 10.0);
    let (y_lo, y_hi) = (
        10f64.powf(y_min.log10().floor()),
        10f64.powf(y_max.log10().ceil()),
    );

    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (860, 520)).into_drawing_area();
        draw(root.fill(&WHITE))?;
        let (plot, legend) = root.split_horizontally(650);
        let mut chart = draw(
            ChartBuilder::on(&plot)
                .caption(
                    format!(
                        "{}: GPU ms per frame phase against blade count (log scales)",
                        b.device
                    ),
                    ("sans-serif", 15),
                )
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(
                    (x_min / 1.25..x_max * 1.25).log_scale(),
                    (y_lo..y_hi).log_scale(),
                ),
        )?;
        draw(
            chart
                .configure_mesh()
                .x_desc("blades")
                .y_desc("ms")
                .x_label_formatter(&|&x| blade_count(x))
                .y_label_formatter(&|&y| format!("{y}"))
                .draw(),
        )?;
        for (_, color, of_paper, opacity, points) in &series {
            let style = color.mix(*opacity).stroke_width(2);
            draw(chart.draw_series(LineSeries::new(points.iter().copied(), style)))?;
            if *of_paper {
                let dots = points.iter().map(|&p| Circle::new(p, 3, style.filled()));
                draw(chart.draw_series(dots))?;
            }
        }
        for (i, (label, color, _, opacity, _)) in series.iter().enumerate() {
            let y = 40 + i as i32 * 18;
            let style = color.mix(*opacity).filled();
            draw(legend.draw(&Rectangle::new([(4, y - 3), (28, y + 3)], style)))?;
            draw(legend.draw(&Text::new(
                label.clone(),
                (34, y - 6),
                ("sans-serif", 12).into_font(),
            )))?;
        }
        draw(root.present())?;
    }
    Ok(out)
}

/// 2000 -> "2K", 1500000 -> "1.5M".
fn blade_count(n: f64) -> String {
    match n {
        n if n >= 1e6 => format!("{}M", n / 1e6),
        n if n >= 1e3 => format!("{}K", n / 1e3),
        n => format!("{n}"),
    }
}

/// A plotters failure as meadow's error (drawing into a string has no I/O
/// to fail; this is for data plotters cannot place).
fn draw<T, E: std::error::Error + Send + Sync>(
    result: std::result::Result<T, DrawingAreaErrorKind<E>>,
) -> Result<T> {
    result.map_err(|e| Error::InvalidInput(format!("drawing bench.svg: {e}")))
}
