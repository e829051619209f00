//! `meadow reproduce`: renders every figure scene of the paper and writes
//! `DIR/index.md` and a self-contained `DIR/index.html` (images inlined)
//! that show each figure beside what the paper's figure shows and the
//! parameters used.

use crate::report::claim::OutputClaim;
use std::path::Path;

use crate::commands::on_gpu;
use crate::commands::render::{render_pictures, Picture, RenderReport, RenderRequest};
use crate::commands::trace::{space_time_svg, trace, BladePick, TraceRequest};
use crate::error::Result;
use crate::gpu::GpuOptions;
use crate::report::files;
use crate::report::reproduce::{html, markdown};
pub use crate::report::reproduce::{Diagram, Figure, Rendered, Shot};
use crate::scene::{Scene, ViewMode};

/// Image size and simulated time: `--quick` keeps lavapipe within minutes.
struct Budget {
    width: u32,
    height: u32,
    sway: f32,
    sequence_frames: u32,
    /// The gust strip: simulated seconds traced, the first ones left out
    /// of the diagram (the wind filling the field), and the picture's time.
    gust_seconds: f64,
    gust_skip: f64,
    gust_start: f32,
    /// The rolling ball: the picture's time (the ball entered the meadow
    /// at 0.5 s; its trail lies behind it).
    roll_start: f32,
}

fn budget(quick: bool) -> Budget {
    if quick {
        Budget {
            width: 320,
            height: 180,
            sway: 0.5,
            sequence_frames: 3,
            gust_seconds: 12.0,
            gust_skip: 4.0,
            gust_start: 6.0,
            roll_start: 3.0,
        }
    } else {
        Budget {
            width: 1280,
            height: 720,
            sway: 2.0,
            sequence_frames: 8,
            gust_seconds: 30.0,
            gust_skip: 13.0,
            gust_start: 15.0,
            roll_start: 5.0,
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
    let strip = Scene::builtin("gust-strip")?;
    let roll = Scene::builtin("roll")?;
    let hills = Scene::builtin("hills")?;
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
            diagram: None,
            shots: vec![
                shot("static", "fig10-few/static", &few, 0.0),
                shot(&sway, "fig10-few/swaying", &few, b.sway),
            ],
        },
        Figure {
            title: "Fig. 10 (right): several bunches",
            paper: "Several bunches of grass, static and swaying in wind from the left.",
            diagram: None,
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
            diagram: None,
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
            diagram: None,
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
            diagram: None,
        },
        Figure {
            title: "Beyond the paper: gusts that travel",
            paper: "Gusts enter from the left as faster air near the ground and are carried \
                    along the strip by the wind: waves run downwind. The diagram is measured \
                    from a trace of the grass (meadow trace): diagonal stripes are waves, their \
                    slope their speed.",
            shots: vec![shot(
                "a 36 m strip in gusts (motion view: blue at rest, red bent)",
                "gusts/strip",
                &strip,
                b.gust_start,
            )],
            diagram: Some(Diagram {
                file: SPACE_TIME_FILE.into(),
                caption: format!(
                    "Space-time diagram of the strip's motion, {} s to {} s: each 1 m band's \
                     downwind tip displacement beyond its mean, in its own standard deviations",
                    b.gust_skip, b.gust_seconds
                ),
            }),
        },
        Figure {
            title: "Beyond the paper: touch",
            paper: "The paper leaves collisions as future work. A ball rolls through the \
                    meadow in a breeze: the blades it meets are pushed out of it and pressed, \
                    and rise again behind it as their pressed state decays (docs/physics.md, \
                    \"Colliders\"). The ball blocks the wind as it moves.",
            shots: vec![
                shot("the ball half way", "roll/shaded", &roll, b.roll_start),
                motion(shot("its trail", "roll/motion", &roll, b.roll_start)),
            ],
            diagram: None,
        },
        Figure {
            title: "Beyond the paper: a landscape",
            paper: "The paper's meadows are flat. A meadow over a ridge and between hills \
                    (the ground's height field, drawn and shading), a bare path left by its \
                    density mask, the wind crossing the ridge at an angle: the solver sees the \
                    ground as solid (docs/physics.md, \"Wind over a ridge\").",
            shots: vec![shot("in the wind", "hills", &hills, b.sway)],
            diagram: None,
        },
    ])
}

/// Where `reproduce` is, told before each shot starts.
#[derive(Clone, Copy, Debug)]
pub struct ShotProgress<'a> {
    pub figure: &'a str,
    pub shot: &'a str,
    /// Shots done before this one, and in all.
    pub done: usize,
    pub total: usize,
    pub elapsed_s: f64,
}

impl ShotProgress<'_> {
    /// Seconds left if the shots to come take as long as the ones so far
    /// did on average (None before the first is done).
    pub fn seconds_left(&self) -> Option<f64> {
        (self.done > 0).then(|| self.elapsed_s / self.done as f64 * (self.total - self.done) as f64)
    }
}

/// Renders every figure into `out` and writes the two index files.
/// `on_shot` hears of each shot before it starts (for progress output).
pub fn reproduce(
    out: &Path,
    quick: bool,
    overwrite: bool,
    gpu: &GpuOptions,
    on_shot: &mut dyn FnMut(ShotProgress),
) -> Result<Vec<Rendered>> {
    let b = budget(quick);
    let figures = plan(quick)?;
    files::ensure_dir(out)?;
    // Each shot's folder is its render's to claim; here the indexes, and
    // the gust diagram beside the strip's shot.
    let gusts = out.join(SPACE_TIME_DIR);
    let index = OutputClaim::new(
        out,
        &[INDEX_MD.to_string(), INDEX_HTML.to_string()],
        overwrite,
    )?;
    let diagram_claim = OutputClaim::new(&gusts, &[SPACE_TIME_NAME.to_string()], overwrite)?;
    // The shots, then the gust trace.
    let total = figures.iter().map(|f| f.shots.len()).sum::<usize>() + 1;
    let started = std::time::Instant::now();
    let mut rendered = Vec::new();
    for (index, figure) in figures.iter().enumerate() {
        // Shots of one instant in other views are drawn from one
        // simulation (fig. 13's shaded and motion views, the ball's): the
        // same frames as rendering each alone, simulated once.
        let mut reports: Vec<Option<RenderReport>> = vec![None; figure.shots.len()];
        for (first, s) in figure.shots.iter().enumerate() {
            if reports[first].is_some() {
                continue;
            }
            let same: Vec<usize> = (first..figure.shots.len())
                .filter(|&k| reports[k].is_none() && figure.shots[k].same_instant(s))
                .collect();
            on_shot(ShotProgress {
                figure: figure.title,
                shot: &s.label,
                done: rendered.len() + reports.iter().flatten().count(),
                total,
                elapsed_s: started.elapsed().as_secs_f64(),
            });
            let mut request = RenderRequest::from_scene(s.scene.clone(), gpu.clone());
            request.width = b.width;
            request.height = b.height;
            request.view = s.view;
            request.animation.frames = s.frames;
            request.animation.fps = s.fps;
            request.animation.start = s.start;
            request.overwrite = overwrite;
            let pictures: Vec<Picture> = same
                .iter()
                .map(|&k| Picture {
                    view: figure.shots[k].view,
                    dir: out.join(&figure.shots[k].dir),
                })
                .collect();
            let done = render_pictures(&request, &pictures, &mut |_| true)?;
            for (k, report) in same.into_iter().zip(done) {
                reports[k] = Some(report);
            }
        }
        for (s, report) in figure.shots.iter().zip(reports) {
            rendered.push(Rendered {
                figure: index,
                label: s.label.clone(),
                dir: s.dir.clone(),
                scene: s.scene.clone(),
                report: report.expect("every shot rendered"),
            });
        }
    }
    on_shot(ShotProgress {
        figure: "Beyond the paper: gusts that travel",
        shot: "space-time diagram (tracing the strip)",
        done: rendered.len(),
        total,
        elapsed_s: started.elapsed().as_secs_f64(),
    });
    let diagram = gust_diagram(&b, gpu)?;
    files::ensure_dir(&gusts)?;
    diagram_claim.begin()?;
    diagram_claim.write(SPACE_TIME_NAME, diagram.as_bytes())?;
    index.begin()?;
    index.write(INDEX_MD, markdown(&figures, &rendered, quick).as_bytes())?;
    index.write(
        INDEX_HTML,
        html(&figures, &rendered, out, quick)?.as_bytes(),
    )?;
    Ok(rendered)
}

const INDEX_MD: &str = "index.md";
const INDEX_HTML: &str = "index.html";
/// The gust strip's space-time diagram: SPACE_TIME_DIR/SPACE_TIME_NAME.
const SPACE_TIME_DIR: &str = "gusts";
const SPACE_TIME_NAME: &str = "space_time.svg";
const SPACE_TIME_FILE: &str = "gusts/space_time.svg";

/// Traces the gust strip and draws its space-time diagram (1 m bands).
fn gust_diagram(b: &Budget, gpu: &GpuOptions) -> Result<String> {
    let request = TraceRequest {
        scene: Scene::builtin("gust-strip")?,
        seconds: b.gust_seconds,
        every: 6,
        blades: BladePick::All,
        wind: false,
        diagram_from: b.gust_skip,
        gpu: gpu.clone(),
    };
    request.validate()?;
    let (run, validation) = on_gpu(&request.gpu, |gpu| trace(gpu, &request, &mut |_, _| true))?;
    validation.check()?;
    space_time_svg(
        &run,
        b.gust_skip,
        "gust-strip: tip displacement along the wind over time",
    )
}

#[cfg(test)]
mod tests {
    use super::ShotProgress;

    #[test]
    fn time_left_follows_the_average_shot_so_far() {
        let at = |done, elapsed_s| ShotProgress {
            figure: "f",
            shot: "s",
            done,
            total: 11,
            elapsed_s,
        };
        assert_eq!(at(0, 0.0).seconds_left(), None);
        assert_eq!(at(2, 10.0).seconds_left(), Some(45.0));
        assert_eq!(at(11, 55.0).seconds_left(), Some(0.0));
    }
}
