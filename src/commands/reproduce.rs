//! `meadow reproduce`: renders every figure scene of the paper and writes
//! `DIR/index.md` and a self-contained `DIR/index.html` (images inlined)
//! that show each figure beside what the paper's figure shows and the
//! parameters used.

use std::fmt::Write as _;
use std::path::Path;

use base64::Engine as _;

use crate::commands::render::{render_to_dir, RenderReport, RenderRequest};
use crate::error::Result;
use crate::gpu::GpuOptions;
use crate::report::files;
use crate::scene::{Scene, ViewMode};

/// One rendered picture (or frame sequence) of a figure.
pub struct Shot {
    pub label: String,
    /// Folder under DIR for its frames.
    pub dir: String,
    pub scene: Scene,
    pub view: ViewMode,
    pub frames: u32,
    pub fps: f32,
    /// Simulated seconds before the first frame.
    pub start: f32,
}

pub struct Figure {
    pub title: &'static str,
    /// What the paper's figure shows.
    pub paper: &'static str,
    pub shots: Vec<Shot>,
}

/// Image size and simulated time: `--quick` keeps lavapipe within minutes.
struct Budget {
    width: u32,
    height: u32,
    sway: f32,
    sequence_frames: u32,
}

fn budget(quick: bool) -> Budget {
    if quick {
        Budget {
            width: 320,
            height: 180,
            sway: 0.5,
            sequence_frames: 3,
        }
    } else {
        Budget {
            width: 1280,
            height: 720,
            sway: 2.0,
            sequence_frames: 8,
        }
    }
}

fn shot(label: &str, dir: &str, scene: &Scene, start: f32) -> Shot {
    Shot {
        label: label.into(),
        dir: dir.into(),
        view: scene.render.view,
        frames: 1,
        fps: scene.render.fps,
        start,
        scene: scene.clone(),
    }
}

/// The figures and their shots.
pub fn plan(quick: bool) -> Result<Vec<Figure>> {
    let b = budget(quick);
    let few = Scene::builtin("fig10-few-bunches")?;
    let several = Scene::builtin("fig10-several-bunches")?;
    let rotating = Scene::builtin("fig11-meadow-rotating")?;
    let lod = Scene::builtin("fig12-lod")?;
    let obstacles = Scene::builtin("fig13-obstacles")?;
    let mut open = obstacles.clone();
    open.wind.obstacles.clear();
    open.name = "fig13-obstacles (obstacles removed)".into();

    let sway = format!("swaying, {} s into the wind", b.sway);
    let mut sequence = shot(
        "frame sequence under the rotating wind",
        "fig11",
        &rotating,
        0.0,
    );
    sequence.frames = b.sequence_frames;
    let lod_shaded = Shot {
        view: ViewMode::Shaded,
        ..shot("the same meadow, shaded", "fig12-shaded", &lod, 0.0)
    };
    let motion = |s: Shot| Shot {
        view: ViewMode::Motion,
        label: format!("{} (motion view: blue at rest, red bent)", s.label),
        ..s
    };
    Ok(vec![
        Figure {
            title: "Fig. 10 (left): a few bunches",
            paper: "A few bunches of grass, static and swaying in wind from the left.",
            shots: vec![
                shot("static", "fig10-few/static", &few, 0.0),
                shot(&sway, "fig10-few/swaying", &few, b.sway),
            ],
        },
        Figure {
            title: "Fig. 10 (right): several bunches",
            paper: "Several bunches of grass, static and swaying in wind from the left.",
            shots: vec![
                shot("static", "fig10-several/static", &several, 0.0),
                shot(&sway, "fig10-several/swaying", &several, b.sway),
            ],
        },
        Figure {
            title: "Fig. 11: a meadow under a rotating wind",
            paper:
                "A meadow swaying under a wind whose direction rotates, over a sequence of frames.",
            shots: vec![sequence],
        },
        Figure {
            title: "Fig. 12: level of detail",
            paper:
                "Level of detail on a meadow: near blades finely tessellated, far ones coarsely.",
            shots: vec![
                shot(
                    "LOD view: red 20 segments, yellow 10, blue 3",
                    "fig12-lod",
                    &lod,
                    0.0,
                ),
                lod_shaded,
            ],
        },
        Figure {
            title: "Fig. 13: obstacles",
            paper: "Wind blocked by obstacles: the grass behind them stays calm.",
            shots: vec![
                shot("with obstacles", "fig13/with", &obstacles, b.sway),
                shot("without obstacles", "fig13/without", &open, b.sway),
                motion(shot(
                    "with obstacles",
                    "fig13/with-motion",
                    &obstacles,
                    b.sway,
                )),
                motion(shot(
                    "without obstacles",
                    "fig13/without-motion",
                    &open,
                    b.sway,
                )),
            ],
        },
    ])
}

/// One shot's result, for the index.
pub struct Rendered {
    pub figure: usize,
    pub label: String,
    pub dir: String,
    /// The scene as rendered (for the parameters shown beside it).
    pub scene: Scene,
    pub report: RenderReport,
}

/// Renders every figure into `out` and writes the two index files.
/// `on_shot` hears of each shot before it starts (for progress output).
pub fn reproduce(
    out: &Path,
    quick: bool,
    gpu: &GpuOptions,
    on_shot: &mut dyn FnMut(&str, &str),
) -> Result<Vec<Rendered>> {
    let b = budget(quick);
    let figures = plan(quick)?;
    files::ensure_dir(out)?;
    let mut rendered = Vec::new();
    for (index, figure) in figures.iter().enumerate() {
        for s in &figure.shots {
            on_shot(figure.title, &s.label);
            let mut request = RenderRequest::from_scene(s.scene.clone(), gpu.clone());
            request.width = b.width;
            request.height = b.height;
            request.view = s.view;
            request.animation.frames = s.frames;
            request.animation.fps = s.fps;
            request.animation.start = s.start;
            let report = render_to_dir(&request, &out.join(&s.dir))?;
            rendered.push(Rendered {
                figure: index,
                label: s.label.clone(),
                dir: s.dir.clone(),
                scene: s.scene.clone(),
                report,
            });
        }
    }
    files::write_atomic(
        &out.join("index.md"),
        markdown(&figures, &rendered, quick).as_bytes(),
    )?;
    files::write_atomic(
        &out.join("index.html"),
        html(&figures, &rendered, out, quick)?.as_bytes(),
    )?;
    Ok(rendered)
}

/// The parameters a reader needs to judge one shot.
fn parameters(r: &RenderReport, scene: &Scene) -> String {
    let wind = &scene.wind;
    let mut drivers = Vec::new();
    if let Some(inflow) = &wind.inflow {
        drivers.push(format!(
            "inflow {} m/s from the left, gust amplitude {}",
            inflow.speed, inflow.gust.amplitude
        ));
    }
    for s in &wind.sources {
        drivers.push(format!(
            "source of {} m/s^2, radius {} m, turning {} rad/s",
            s.strength, s.radius, s.rotation_speed
        ));
    }
    if !wind.obstacles.is_empty() {
        drivers.push(format!("{} obstacles", wind.obstacles.len()));
    }
    if drivers.is_empty() {
        drivers.push("still air".into());
    }
    format!(
        "{} blades, seed {}; {}x{}, MSAA {}x of {}x asked, LOD {}, {} view; frames at {} s of simulated time ({} steps of {:.4} s); wind grid {}x{}x{}, {} Jacobi iterations, {}; {} [{}]",
        r.blades,
        r.seed,
        r.width,
        r.height,
        r.msaa_used,
        r.msaa_requested,
        if r.lod { "on" } else { "off" },
        serde_json::to_value(r.view).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default(),
        frame_times(r),
        r.sim_steps,
        r.sim_dt,
        wind.cells[0],
        wind.cells[1],
        wind.cells[2],
        wind.jacobi_iterations,
        drivers.join(", "),
        r.device,
        r.device_type,
    )
}

fn frame_times(r: &RenderReport) -> String {
    let a = &r.animation;
    let times: Vec<String> = (0..a.frames)
        .map(|f| format!("{:.2}", a.time_of(f)))
        .collect();
    times.join(", ")
}

fn markdown(figures: &[Figure], rendered: &[Rendered], quick: bool) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# meadow: the paper's figures, reproduced\n");
    let _ = writeln!(
        md,
        "Lee, Lo, Chu and Chang, \"A simulation on grass swaying with dynamic wind force\" (The Visual Computer, 2016).{}\n",
        if quick {
            " Quick mode: small images and short simulated times."
        } else {
            ""
        }
    );
    for (i, figure) in figures.iter().enumerate() {
        let _ = writeln!(md, "## {}\n", figure.title);
        let _ = writeln!(md, "Paper: {}\n", figure.paper);
        for r in rendered.iter().filter(|r| r.figure == i) {
            let scene = &r.scene;
            let _ = writeln!(md, "**{}** ({})\n", r.label, scene.caption);
            for frame in &r.report.frames {
                let _ = write!(md, "![{}]({}/{}) ", r.label, r.dir, frame);
            }
            let _ = writeln!(md, "\n\n{}\n", parameters(&r.report, scene));
        }
    }
    md
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn html(figures: &[Figure], rendered: &[Rendered], out: &Path, quick: bool) -> Result<String> {
    let mut h = String::new();
    h.push_str(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>meadow: the paper's figures, reproduced</title>\
         <style>body{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}\
         figure{display:inline-block;margin:0.5em;vertical-align:top}\
         img{max-width:640px;width:100%}.params{color:#444;font-size:0.9em}\
         .paper{background:#f4f1e8;padding:0.5em;border-left:4px solid #b8a070}</style>\
         </head><body>\n<h1>meadow: the paper's figures, reproduced</h1>\n",
    );
    let _ = writeln!(
        h,
        "<p>Lee, Lo, Chu and Chang, &ldquo;A simulation on grass swaying with dynamic wind force&rdquo; (The Visual Computer, 2016).{}</p>",
        if quick {
            " Quick mode: small images and short simulated times."
        } else {
            ""
        }
    );
    for (i, figure) in figures.iter().enumerate() {
        let _ = writeln!(h, "<h2>{}</h2>", escape(figure.title));
        let _ = writeln!(h, "<p class=\"paper\">Paper: {}</p>", escape(figure.paper));
        for r in rendered.iter().filter(|r| r.figure == i) {
            let scene = &r.scene;
            let _ = writeln!(
                h,
                "<h3>{} <small>({})</small></h3>",
                escape(&r.label),
                escape(&scene.caption)
            );
            // Every frame of a shot is written (no --every): the n-th file
            // is frame n.
            for (frame, time) in r.report.frames.iter().zip(0..) {
                let path = out.join(&r.dir).join(frame);
                let png = std::fs::read(&path).map_err(|e| crate::Error::io(&path, e))?;
                let data = base64::engine::general_purpose::STANDARD.encode(png);
                let _ = writeln!(
                    h,
                    "<figure><img alt=\"{}\" src=\"data:image/png;base64,{data}\"><figcaption>t = {:.2} s</figcaption></figure>",
                    escape(&r.label),
                    r.report.animation.time_of(time)
                );
            }
            let _ = writeln!(
                h,
                "<p class=\"params\">{}</p>",
                escape(&parameters(&r.report, scene))
            );
        }
    }
    h.push_str("</body></html>\n");
    Ok(h)
}
