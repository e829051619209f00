//! The index of `meadow reproduce`: what each paper figure shows, the shots
//! rendered for it and their parameters, as DIR/index.md and a
//! self-contained DIR/index.html (images inlined).

use std::fmt::Write as _;
use std::path::Path;

use base64::Engine as _;

use crate::error::Result;
use crate::report::render::RenderReport;
use crate::scene::{Scene, ViewMode};

/// One rendered picture (or frame sequence) of a figure.
#[derive(Clone)]
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
    /// Also a video of its frames, this file in its folder (ffmpeg; .mp4).
    pub video: Option<String>,
}

impl Shot {
    /// Whether `other` shows the same simulated frames, perhaps in another
    /// view: the same scene, frames, rate and start.
    pub fn same_instant(&self, other: &Shot) -> bool {
        self.scene == other.scene
            && (self.frames, self.fps, self.start) == (other.frames, other.fps, other.start)
    }
}

pub struct Figure {
    pub title: &'static str,
    /// What the paper's figure shows (or, beyond the paper, what to see).
    pub paper: &'static str,
    pub shots: Vec<Shot>,
    /// Measured diagrams shown after the shots.
    pub diagrams: Vec<Diagram>,
}

/// An SVG the command wrote under DIR, with what it shows.
pub struct Diagram {
    /// Path under DIR.
    pub file: String,
    pub caption: String,
}

/// One shot's result, for the index.
pub struct Rendered {
    pub figure: usize,
    pub label: String,
    pub dir: String,
    /// The scene as rendered (for the parameters shown beside it).
    pub scene: Scene,
    pub report: RenderReport,
    /// The video asked for: its file name in `dir` when written, or why it
    /// was not (no ffmpeg on this machine).
    pub video: Option<std::result::Result<String, String>>,
}

/// The frames an index shows of a shot of `frames`: every one up to
/// four, else four spread from the first to the last (a video shot has
/// them all).
fn shown(frames: usize) -> Vec<usize> {
    if frames <= 4 {
        (0..frames).collect()
    } else {
        (0..4).map(|k| k * (frames - 1) / 3).collect()
    }
}

/// "Paper: ..." for the paper's figures; beyond the paper, what to see.
fn paper_line(figure: &Figure) -> String {
    if figure.title.starts_with("Beyond the paper") {
        figure.paper.to_string()
    } else {
        format!("Paper: {}", figure.paper)
    }
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
        "{} blades, seed {}; {}x{}, MSAA {}x of {}x asked, LOD {}, {} view; frames at {} s of simulated time ({} steps of {:.4} s); wind grid {}x{}x{}, {}, {}; angle caps {:.3}% of blade-steps; {} [{}]",
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
        crate::report::wind::describe(wind.solver, wind.jacobi_iterations, wind.v_cycles),
        drivers.join(", "),
        100.0 * r.cap_fraction,
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

pub fn markdown(figures: &[Figure], rendered: &[Rendered], quick: bool) -> String {
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
        let _ = writeln!(md, "{}\n", paper_line(figure));
        for r in rendered.iter().filter(|r| r.figure == i) {
            let scene = &r.scene;
            let _ = writeln!(md, "**{}** ({})\n", r.label, scene.caption);
            for k in shown(r.report.frames.len()) {
                let _ = write!(md, "![{}]({}/{}) ", r.label, r.dir, r.report.frames[k]);
            }
            if let Some(gif) = &r.report.gif {
                let _ = write!(md, "\n\nMoving: ![{} (GIF)]({}/{gif})", r.label, r.dir);
            }
            if let Some(waves) = &r.report.light_waves {
                let _ = write!(
                    md,
                    "\n\n{}",
                    crate::report::render::light_waves_line(waves).trim_end()
                );
            }
            match &r.video {
                Some(Ok(name)) => {
                    let _ = write!(md, "\n\nVideo: [{name}]({}/{name})", r.dir);
                }
                Some(Err(why)) => {
                    let _ = write!(md, "\n\nNo video: {why}");
                }
                None => {}
            }
            let _ = writeln!(md, "\n\n{}\n", parameters(&r.report, scene));
        }
        for d in &figure.diagrams {
            let _ = writeln!(md, "![{}]({})\n\n{}\n", d.caption, d.file, d.caption);
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

/// One shot in index.html: its frames, GIF and video inlined, its waves
/// of light and its parameters.
fn shot_html(r: &Rendered, out: &Path) -> Result<String> {
    let mut h = String::new();
    let scene = &r.scene;
    let _ = writeln!(
        h,
        "<h3>{} <small>({})</small></h3>",
        escape(&r.label),
        escape(&scene.caption)
    );
    // Every frame of a shot is written (no --every): the n-th file
    // is frame n.
    for time in shown(r.report.frames.len()) {
        let path = out.join(&r.dir).join(&r.report.frames[time]);
        let png = std::fs::read(&path).map_err(|e| crate::Error::io(&path, e))?;
        let data = base64::engine::general_purpose::STANDARD.encode(png);
        let _ = writeln!(
            h,
            "<figure><img alt=\"{}\" src=\"data:image/png;base64,{data}\"><figcaption>t = {:.2} s</figcaption></figure>",
            escape(&r.label),
            r.report.animation.time_of(time as u32)
        );
    }
    if let Some(gif) = &r.report.gif {
        let path = out.join(&r.dir).join(gif);
        let bytes = std::fs::read(&path).map_err(|e| crate::Error::io(&path, e))?;
        let data = base64::engine::general_purpose::STANDARD.encode(bytes);
        let _ = writeln!(
            h,
            "<figure><img alt=\"{} (moving)\" src=\"data:image/gif;base64,{data}\"><figcaption>moving ({gif})</figcaption></figure>",
            escape(&r.label)
        );
    }
    if let Some(waves) = &r.report.light_waves {
        let _ = writeln!(
            h,
            "<p class=\"params\">{}</p>",
            escape(crate::report::render::light_waves_line(waves).trim_end())
        );
    }
    match &r.video {
        Some(Ok(name)) => {
            let path = out.join(&r.dir).join(name);
            let mp4 = std::fs::read(&path).map_err(|e| crate::Error::io(&path, e))?;
            let data = base64::engine::general_purpose::STANDARD.encode(mp4);
            let _ = writeln!(
                h,
                "<figure><video controls loop src=\"data:video/mp4;base64,{data}\"></video><figcaption>{}</figcaption></figure>",
                escape(name)
            );
        }
        Some(Err(why)) => {
            let _ = writeln!(h, "<p class=\"params\">No video: {}</p>", escape(why));
        }
        None => {}
    }
    let _ = writeln!(
        h,
        "<p class=\"params\">{}</p>",
        escape(&parameters(&r.report, scene))
    );
    Ok(h)
}

pub fn html(figures: &[Figure], rendered: &[Rendered], out: &Path, quick: bool) -> Result<String> {
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
        let _ = writeln!(h, "<p class=\"paper\">{}</p>", escape(&paper_line(figure)));
        for r in rendered.iter().filter(|r| r.figure == i) {
            h += &shot_html(r, out)?;
        }
        for d in &figure.diagrams {
            let path = out.join(&d.file);
            let svg = std::fs::read(&path).map_err(|e| crate::Error::io(&path, e))?;
            let data = base64::engine::general_purpose::STANDARD.encode(svg);
            let _ = writeln!(
                h,
                "<figure><img alt=\"{0}\" src=\"data:image/svg+xml;base64,{data}\"><figcaption>{0}</figcaption></figure>",
                escape(&d.caption)
            );
        }
    }
    h.push_str("</body></html>\n");
    Ok(h)
}
