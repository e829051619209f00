//! `meadow reproduce`: renders every figure scene of the paper and writes
//! `DIR/index.md` and a self-contained `DIR/index.html` (images inlined)
//! that show each figure beside what the paper's figure shows and the
//! parameters used.

use crate::report::claim::OutputClaim;
use std::path::Path;

use crate::analysis::trace::Trace;
use crate::commands::render::{
    render_pictures, render_pictures_traced, Picture, RenderReport, RenderRequest,
};
use crate::commands::trace::{
    plan_view_svg, space_time_svg, spectrum_svg, BladePick, TraceRequest, PLAN_VIEW_NAME,
    SPECTRUM_NAME,
};
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
    /// The rolling ball's wind grid (None: the scene's 60 x 20 x 60).
    roll_cells: Option<[u32; 3]>,
    /// The turbulent field: simulated seconds traced (the plan view shows
    /// its last three), and its blades per square metre.
    field_seconds: f64,
    field_density: f32,
    /// The flight over steppe: its frames (a video of them) and their rate.
    flight_frames: u32,
    flight_fps: f32,
    /// Honami: its frames (None: the scene's own, a gust period) and
    /// whether the meadow is cut to 8 x 6 m.
    honami_frames: Option<u32>,
    honami_small: bool,
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
            // Half the scene's cells on each axis (0.5 m across, the
            // ball's radius 0.4 m): the ball still blocks the breeze,
            // and its 180 steps cost an eighth of the wind they did,
            // which was most of the shot.
            roll_cells: Some([30, 10, 30]),
            field_seconds: 10.0,
            field_density: 1.5,
            flight_frames: 3,
            flight_fps: 2.0,
            honami_frames: Some(4),
            honami_small: true,
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
            roll_cells: None,
            field_seconds: 40.0,
            field_density: 3.0,
            flight_frames: 48,
            flight_fps: 8.0,
            honami_frames: None,
            honami_small: false,
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
        video: None,
    }
}

/// gust-strip's wind over a 60 x 60 m field, its inflow's gusts left out:
/// the turbulence alone, patches everywhere (issue 39's picture), seen
/// from a corner.
pub fn turbulent_field(density: f32) -> Result<Scene> {
    let mut scene = Scene::builtin("gust-strip")?;
    scene.name = "turbulent-field".into();
    scene.caption =
        "gust-strip's turbulence over a 60 x 60 m field, without the inflow's gusts".into();
    for meadow in &mut scene.grass.meadow {
        meadow.center = [0.0, 0.0];
        meadow.size = [60.0, 60.0];
        meadow.count = None;
        meadow.density = Some(density);
    }
    scene.ground.half_extent = 60.0;
    scene.wind.cells = [30, 8, 30];
    if let Some(inflow) = &mut scene.wind.inflow {
        inflow.gust.amplitude = 0.0;
    }
    scene.camera.position = [-40.0, 24.0, 40.0];
    scene.camera.target = [0.0, 0.0, 0.0];
    scene.validate()?;
    Ok(scene)
}

/// honami, or with `small` its meadow cut to 8 x 6 m (the camera at its
/// downwind edge, the wind grid to match): the same waves at a tenth of
/// the blades.
pub fn honami(small: bool) -> Result<Scene> {
    let mut scene = Scene::builtin("honami")?;
    if small {
        scene.grass.meadow[0].size = [8.0, 6.0];
        scene.wind.cells = [24, 12, 20];
        scene.camera.position = [4.5, 1.7, 0.0];
        scene.camera.target = [-3.0, 0.0, 0.0];
        scene.render.start = 3.0;
        scene.validate()?;
    }
    Ok(scene)
}

/// The figures and their shots, one function each.
pub fn plan(quick: bool) -> Result<Vec<Figure>> {
    let b = budget(quick);
    Ok(vec![
        fig10_few(&b)?,
        fig10_several(&b)?,
        fig11(&b)?,
        fig12()?,
        fig13(&b)?,
        gusts(&b)?,
        turbulence(&b)?,
        waves_of_light(&b)?,
        touch(&b)?,
        landscape(&b)?,
        grass_without_edges(&b)?,
    ])
}

/// The label of a shot `b.sway` seconds into the wind.
fn swaying(b: &Budget) -> String {
    format!("swaying, {} s into the wind", b.sway)
}

/// A shot in the motion view, its label saying so.
fn motion(s: Shot) -> Shot {
    Shot {
        view: ViewMode::Motion,
        label: format!("{} (motion view: blue at rest, red bent)", s.label),
        ..s
    }
}

/// Fig. 10 (left): a few bunches, static and swaying.
fn fig10_few(b: &Budget) -> Result<Figure> {
    let few = Scene::builtin("fig10-few-bunches")?;
    let sway = swaying(b);
    Ok(Figure {
        title: "Fig. 10 (left): a few bunches",
        paper: "A few bunches of grass, static and swaying in wind from the left.",
        diagrams: Vec::new(),
        shots: vec![
            shot("static", "fig10-few/static", &few, 0.0),
            shot(&sway, "fig10-few/swaying", &few, b.sway),
        ],
    })
}

/// Fig. 10 (right): several bunches, static and swaying.
fn fig10_several(b: &Budget) -> Result<Figure> {
    let several = Scene::builtin("fig10-several-bunches")?;
    let sway = swaying(b);
    Ok(Figure {
        title: "Fig. 10 (right): several bunches",
        paper: "Several bunches of grass, static and swaying in wind from the left.",
        diagrams: Vec::new(),
        shots: vec![
            shot("static", "fig10-several/static", &several, 0.0),
            shot(&sway, "fig10-several/swaying", &several, b.sway),
        ],
    })
}

/// Fig. 11: a sequence of frames under the rotating wind.
fn fig11(b: &Budget) -> Result<Figure> {
    let rotating = Scene::builtin("fig11-meadow-rotating")?;
    let mut sequence = shot(
        "frame sequence under the rotating wind",
        "fig11",
        &rotating,
        0.0,
    );
    sequence.frames = b.sequence_frames;
    Ok(Figure {
        title: "Fig. 11: a meadow under a rotating wind",
        paper: "A meadow swaying under a wind whose direction rotates, over a sequence of frames.",
        shots: vec![sequence],
        diagrams: Vec::new(),
    })
}

/// Fig. 12: the LOD view and the same meadow shaded.
fn fig12() -> Result<Figure> {
    let lod = Scene::builtin("fig12-lod")?;
    let lod_shaded = Shot {
        view: ViewMode::Shaded,
        ..shot("the same meadow, shaded", "fig12-shaded", &lod, 0.0)
    };
    Ok(Figure {
        title: "Fig. 12: level of detail",
        paper: "Level of detail on a meadow: near blades finely tessellated, far ones coarsely.",
        shots: vec![
            shot(
                "LOD view: red 20 segments, yellow 10, blue 3",
                "fig12-lod",
                &lod,
                0.0,
            ),
            lod_shaded,
        ],
        diagrams: Vec::new(),
    })
}

/// Fig. 13: with and without the obstacles, shaded and in the motion view.
fn fig13(b: &Budget) -> Result<Figure> {
    let obstacles = Scene::builtin("fig13-obstacles")?;
    let mut open = obstacles.clone();
    open.wind.obstacles.clear();
    open.name = "fig13-obstacles (obstacles removed)".into();
    Ok(Figure {
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
        diagrams: Vec::new(),
    })
}

/// Gusts that travel: the strip and its space-time diagram.
fn gusts(b: &Budget) -> Result<Figure> {
    let strip = Scene::builtin("gust-strip")?;
    Ok(Figure {
        title: GUSTS_TITLE,
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
        diagrams: vec![Diagram {
            file: SPACE_TIME_FILE.into(),
            caption: format!(
                "Space-time diagram of the strip's motion, {} s to {} s: each 1 m band's \
                 downwind tip displacement beyond its mean, in its own standard deviations",
                b.gust_skip, b.gust_seconds
            ),
        }],
    })
}

/// Turbulence everywhere: the field, its plan view and spectrum.
fn turbulence(b: &Budget) -> Result<Figure> {
    let field = turbulent_field(b.field_density)?;
    Ok(Figure {
        title: TURBULENCE_TITLE,
        paper: "Turbulence everywhere: a fluctuating, divergence-free part of the wind \
                (intensity 0.3, length scale 4 m) carried by the mean wind and renewed \
                all over the field (docs/method.md). From above, the tips bent downwind \
                are patches a few metres across, not fronts, moving downwind from one \
                second to the next; the tips' spectrum is drawn beside the blades' \
                natural frequencies (docs/physics.md, \"Turbulence everywhere\").",
        shots: vec![shot(
            "a 60 x 60 m field in turbulence (motion view: blue at rest, red bent)",
            "turbulence/field",
            &field,
            (FIELD_SKIP + 2.0) as f32,
        )],
        diagrams: vec![
            Diagram {
                file: format!("{TURBULENCE_DIR}/{PLAN_VIEW_NAME}"),
                caption: format!(
                    "The field from above at {:.0}, {:.0} and {:.0} s: each cell's downwind \
                     tip displacement beyond its mean, in its own standard deviations",
                    b.field_seconds - 2.0,
                    b.field_seconds - 1.0,
                    b.field_seconds
                ),
            },
            Diagram {
                file: format!("{TURBULENCE_DIR}/{SPECTRUM_NAME}"),
                caption: format!(
                    "The tips' spectrum from {FIELD_SKIP} s on, beside the blades' natural \
                     frequencies"
                ),
            },
        ],
    })
}

/// Waves of light: honami shaded and in the motion view.
fn waves_of_light(b: &Budget) -> Result<Figure> {
    let honami = honami(b.honami_small)?;
    let waves = Shot {
        frames: b.honami_frames.unwrap_or(honami.render.frames),
        fps: honami.render.fps,
        ..shot(
            "shaded: looking into the wind",
            "honami/shaded",
            &honami,
            honami.render.start,
        )
    };
    Ok(Figure {
        title: "Beyond the paper: waves of light",
        paper: "Honami: a gust crossing a dense meadow bows its blades together, and \
                their faces and sheen turn toward or away from the sun, the sky and the \
                eye (a leaf's optics, docs/method.md section 4b): bands of light run \
                across the shaded field at the wind's speed. The motion view beside it \
                shows the same instants in false colour; the line under the shaded shot \
                says how far its light varies and follows the blades' displacement \
                (meadow render --light-waves; docs/physics.md, \"Waves of light\").",
        shots: vec![
            waves.clone(),
            motion(Shot {
                label: "the same frames".into(),
                dir: "honami/motion".into(),
                ..waves
            }),
        ],
        diagrams: Vec::new(),
    })
}

/// Touch: the rolling ball and its trail.
fn touch(b: &Budget) -> Result<Figure> {
    let mut roll = Scene::builtin("roll")?;
    if let Some(cells) = b.roll_cells {
        roll.wind.cells = cells;
        roll.validate()?;
    }
    Ok(Figure {
        title: "Beyond the paper: touch",
        paper: "The paper leaves collisions as future work. A ball rolls through the \
                meadow in a breeze: the blades it meets are pushed out of it and pressed, \
                and rise again behind it as their pressed state decays (docs/physics.md, \
                \"Colliders\"). The ball blocks the wind as it moves.",
        shots: vec![
            shot("the ball half way", "roll/shaded", &roll, b.roll_start),
            motion(shot("its trail", "roll/motion", &roll, b.roll_start)),
        ],
        diagrams: Vec::new(),
    })
}

/// A landscape: the hills in the wind.
fn landscape(b: &Budget) -> Result<Figure> {
    let hills = Scene::builtin("hills")?;
    Ok(Figure {
        title: "Beyond the paper: a landscape",
        paper: "The paper's meadows are flat. A meadow over a ridge and between hills \
                (the ground's height field, drawn and shading), a bare path left by its \
                density mask, the wind crossing the ridge at an angle: the solver sees the \
                ground as solid (docs/physics.md, \"Wind over a ridge\").",
        shots: vec![shot("in the wind", "hills", &hills, b.sway)],
        diagrams: Vec::new(),
    })
}

/// Grass without edges: the flight over steppe.
fn grass_without_edges(b: &Budget) -> Result<Figure> {
    let steppe = Scene::builtin("steppe")?;
    // The camera flies 10 m/s: 5 m between frames in quick mode, 1.25 m
    // (8 a second, 6 s, 60 m) in a video.
    let flight = Shot {
        frames: b.flight_frames,
        fps: b.flight_fps,
        video: Some("flight.mp4".into()),
        ..shot("flying over it", "steppe", &steppe, 0.0)
    };
    Ok(Figure {
        title: "Beyond the paper: grass without edges",
        paper: "The paper's meadows are bounded and made once. A [grass.cover] is made on \
                the GPU each frame in 4 m tiles around the camera, each tile's blades from \
                the seed and the tile alone, and each blade the frame may draw leans where \
                its torques balance in the wind at its tip (the quasi-static pose, \
                docs/method.md); within 30 m they carry the paper's dynamics, blended into \
                that pose over the last 4 m. The wind is a window that follows the camera. \
                The camera flies over it at 10 m/s and it never ends (docs/perf.md, \"The \
                cover\"); a video of the flight beside the frames.",
        shots: vec![flight],
        diagrams: Vec::new(),
    })
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
    let turbulence = out.join(TURBULENCE_DIR);
    let field_claim = OutputClaim::new(
        &turbulence,
        &[PLAN_VIEW_NAME.to_string(), SPECTRUM_NAME.to_string()],
        overwrite,
    )?;
    // The gust strip's and the turbulent field's shots are drawn from the
    // simulations their diagrams trace: one simulation each.
    let gust_trace = gust_trace(&b, gpu)?;
    let field_trace = field_trace(&b, gpu)?;
    let total = figures.iter().map(|f| f.shots.len()).sum::<usize>();
    let started = std::time::Instant::now();
    let mut rendered = Vec::new();
    let (mut gust_run, mut field_run) = (None, None);
    for (index, figure) in figures.iter().enumerate() {
        let mut progress = |shot: &str, done_here: usize| {
            on_shot(ShotProgress {
                figure: figure.title,
                shot,
                done: rendered.len() + done_here,
                total,
                elapsed_s: started.elapsed().as_secs_f64(),
            })
        };
        let (traced, run) = match figure.title {
            GUSTS_TITLE => (Some(&gust_trace), &mut gust_run),
            TURBULENCE_TITLE => (Some(&field_trace), &mut field_run),
            _ => (None, &mut None),
        };
        let (shots, trace) = render_figure(figure, &b, out, overwrite, gpu, traced, &mut progress)?;
        *run = trace;
        rendered.extend(shots.into_iter().map(|(s, report, video)| Rendered {
            figure: index,
            label: s.label.clone(),
            dir: s.dir.clone(),
            scene: s.scene.clone(),
            report,
            video,
        }));
    }
    let traced = |run: Option<Trace>, what: &str| {
        run.ok_or_else(|| crate::Error::InvalidInput(format!("the plan has no shot of {what}")))
    };
    let diagram = gust_diagram(&b, &traced(gust_run, "the gust strip")?)?;
    files::ensure_dir(&gusts)?;
    diagram_claim.begin()?;
    diagram_claim.write(SPACE_TIME_NAME, diagram.as_bytes())?;
    let (plan_view, spectrum) = field_diagrams(&b, &traced(field_run, "the turbulent field")?)?;
    files::ensure_dir(&turbulence)?;
    field_claim.begin()?;
    field_claim.write(PLAN_VIEW_NAME, plan_view.as_bytes())?;
    field_claim.write(SPECTRUM_NAME, spectrum.as_bytes())?;
    index.begin()?;
    index.write(INDEX_MD, markdown(&figures, &rendered, quick).as_bytes())?;
    index.write(
        INDEX_HTML,
        html(&figures, &rendered, out, quick)?.as_bytes(),
    )?;
    Ok(rendered)
}

/// A shot's video: its file name, or why there is none.
type Video = Option<std::result::Result<String, String>>;

/// A figure's shots, each with its report and video.
type FigureShots<'f> = Vec<(&'f Shot, RenderReport, Video)>;

/// Renders `figure`'s shots into `out`, telling `progress` of each (its
/// label and the figure's shots done before it). Shots of one instant in
/// other views are drawn from one simulation (fig. 13's shaded and motion
/// views, the ball's): the same frames as rendering each alone, simulated
/// once. With `trace`, the first shot's simulation is also traced (its
/// scene the trace's) and the trace returned.
fn render_figure<'f>(
    figure: &'f Figure,
    b: &Budget,
    out: &Path,
    overwrite: bool,
    gpu: &GpuOptions,
    mut trace: Option<&TraceRequest>,
    progress: &mut dyn FnMut(&str, usize),
) -> Result<(FigureShots<'f>, Option<Trace>)> {
    let mut run = None;
    let mut reports: Vec<Option<RenderReport>> = vec![None; figure.shots.len()];
    let mut videos: Vec<Video> = vec![None; figure.shots.len()];
    for (first, s) in figure.shots.iter().enumerate() {
        if reports[first].is_some() {
            continue;
        }
        let same: Vec<usize> = (first..figure.shots.len())
            .filter(|&k| reports[k].is_none() && figure.shots[k].same_instant(s))
            .collect();
        progress(&s.label, reports.iter().flatten().count());
        let mut request = RenderRequest::from_scene(s.scene.clone(), gpu.clone());
        request.width = b.width;
        request.height = b.height;
        request.view = s.view;
        request.animation.frames = s.frames;
        request.animation.fps = s.fps;
        request.animation.start = s.start;
        request.overwrite = overwrite;
        // A video where ffmpeg is at hand; without it the index says
        // why there is none (the frames need nothing).
        let video = s.video.as_ref().filter(|_| same.len() == 1).map(|name| {
            crate::report::video::find_ffmpeg()
                .map(|_| name.clone())
                .map_err(|_| {
                    "ffmpeg is not on PATH (scripts/ensure-ffmpeg installs it)".to_string()
                })
        });
        if let Some(Ok(name)) = &video {
            request.video = Some(out.join(&s.dir).join(name));
        }
        videos[first] = video;
        let pictures: Vec<Picture> = same
            .iter()
            .map(|&k| Picture {
                view: figure.shots[k].view,
                dir: out.join(&figure.shots[k].dir),
            })
            .collect();
        let done = match trace.take() {
            Some(trace) => {
                let (done, traced) =
                    render_pictures_traced(&request, &pictures, trace, &mut |_| true)?;
                run = Some(traced);
                done
            }
            None => render_pictures(&request, &pictures, &mut |_| true)?,
        };
        for (k, report) in same.into_iter().zip(done) {
            reports[k] = Some(report);
        }
    }
    let shots = figure
        .shots
        .iter()
        .zip(reports)
        .zip(videos)
        .map(|((s, report), video)| (s, report.expect("every shot rendered"), video))
        .collect();
    Ok((shots, run))
}

const INDEX_MD: &str = "index.md";
const INDEX_HTML: &str = "index.html";
/// The gust strip's space-time diagram: SPACE_TIME_DIR/SPACE_TIME_NAME.
const SPACE_TIME_DIR: &str = "gusts";
const SPACE_TIME_NAME: &str = "space_time.svg";
const SPACE_TIME_FILE: &str = "gusts/space_time.svg";

const GUSTS_TITLE: &str = "Beyond the paper: gusts that travel";
const TURBULENCE_TITLE: &str = "Beyond the paper: turbulence everywhere";
/// The turbulent field's plan view and spectrum: TURBULENCE_DIR/...
const TURBULENCE_DIR: &str = "turbulence";
/// Seconds of the field's trace left out of its pictures' statistics (the
/// turbulence filling the field).
const FIELD_SKIP: f64 = 4.0;

/// The trace of every blade of the turbulent field, drawn as its plan
/// view at the last three seconds and its tips' spectrum.
fn field_trace(b: &Budget, gpu: &GpuOptions) -> Result<TraceRequest> {
    let request = TraceRequest {
        scene: turbulent_field(b.field_density)?,
        seconds: b.field_seconds,
        every: 3,
        blades: BladePick::All,
        wind: false,
        diagram_from: FIELD_SKIP,
        gpu: gpu.clone(),
    };
    request.validate()?;
    Ok(request)
}

/// The turbulent field's plan view and its tips' spectrum, from its trace.
fn field_diagrams(b: &Budget, run: &Trace) -> Result<(String, String)> {
    let no_picture = |what: &str| {
        crate::Error::InvalidInput(format!(
            "the turbulent field's trace of {} s gives no {what}",
            b.field_seconds
        ))
    };
    let plan_view = plan_view_svg(
        run,
        FIELD_SKIP,
        "60 x 60 m in turbulence: tips bent downwind from above, a second apart",
    )?
    .ok_or_else(|| no_picture("plan view"))?;
    let spectrum = run
        .tip_spectrum(FIELD_SKIP)
        .ok_or_else(|| no_picture("spectrum"))?;
    let spectrum = spectrum_svg(
        &spectrum,
        run.scaled_tip_spectrum(FIELD_SKIP).as_ref(),
        run.bend_natural_hz().as_ref(),
        run.swing_natural_hz().as_ref(),
        "60 x 60 m in turbulence: the tips' spectrum",
    )?;
    Ok((plan_view, spectrum))
}

/// The trace of every blade of the gust strip, drawn as its space-time
/// diagram (1 m bands).
fn gust_trace(b: &Budget, gpu: &GpuOptions) -> Result<TraceRequest> {
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
    Ok(request)
}

/// The gust strip's space-time diagram, from its trace.
fn gust_diagram(b: &Budget, run: &Trace) -> Result<String> {
    space_time_svg(
        run,
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
