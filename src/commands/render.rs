//! `meadow render` as a library call: validate the request, open the GPU,
//! simulate and render every frame (`frame_0000.png`, ...), write
//! `report.json`, tear everything down and check what validation said.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::analysis::light_waves::{self, LightWaves};
use crate::analysis::trace::Trace;
use crate::commands::on_gpu;
use crate::commands::trace::{TraceRequest, TraceSampler};
use crate::compute::StepPace;
use crate::error::{Error, Result};
use crate::frame::timing::{Phase, TimingSummary};
pub use crate::frame::Animation;
use crate::frame::{CullCounts, FrameRecorder};
use crate::gpu::{Gpu, GpuOptions, ValidationReport};
use crate::model::grass::CapCounts;
use crate::model::multigrid::SolveCounts;
use crate::report::claim::{name_in_folder, OutputClaim};
pub use crate::report::render::{BladeCounts, RenderReport};
use crate::report::video::{self, VideoFormat};
use crate::report::{files, legend};
use crate::scene::{field, Planted, Scene, ViewMode};

pub use crate::scene::check::{MAX_FRAMES, MAX_IMAGE_SIDE};

mod frames;
use frames::{animate, sampled_batch, Animated, GIF_NAME};

#[derive(Clone, Debug)]
pub struct RenderRequest {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    /// Requested MSAA samples; the largest supported count up to this is used.
    pub msaa: u32,
    pub view: ViewMode,
    pub animation: Animation,
    /// Write only every K-th frame (frames 0, K, 2K, ...); the simulation
    /// still runs through the frames in between.
    pub every: u32,
    /// With more than one frame written: also DIR/animation.gif.
    pub gif: bool,
    /// Also a video of the frames written (.mp4: H.264, .webm: VP9), by
    /// ffmpeg, at the rate they are written.
    pub video: Option<PathBuf>,
    /// Replace files in the output folder that an earlier meadow run did
    /// not write, or that were changed since (`report::claim`).
    pub overwrite: bool,
    /// Also measure the waves of light (`analysis::light_waves`): each
    /// frame written is drawn once more in the data view (and shaded,
    /// when no picture is), and report.json holds `light_waves`.
    pub light_waves: bool,
    pub gpu: GpuOptions,
}

impl RenderRequest {
    /// The scene as its `[render]` table says to render it.
    pub fn from_scene(scene: Scene, gpu: GpuOptions) -> Self {
        let r = scene.render.clone();
        Self {
            scene,
            width: r.width,
            height: r.height,
            msaa: r.msaa,
            view: r.view,
            animation: Animation {
                frames: r.frames,
                fps: r.fps,
                start: r.start,
            },
            every: 1,
            gif: true,
            video: None,
            overwrite: false,
            light_waves: r.light_waves,
            gpu,
        }
    }

    /// The scene as this request renders it: the command line's overrides
    /// applied and its `[render]` table set to the request's size, MSAA,
    /// view and animation. Written beside the report as scene.toml, so
    /// `meadow render --scene DIR/scene.toml` renders the run again.
    pub fn scene_as_rendered(&self) -> Scene {
        let mut scene = self.scene.clone();
        scene.render = self.render_settings();
        scene
    }

    /// The request's size, MSAA, view and animation as a `[render]` table.
    fn render_settings(&self) -> crate::scene::RenderSettings {
        crate::scene::RenderSettings {
            width: self.width,
            height: self.height,
            msaa: self.msaa,
            view: self.view,
            frames: self.animation.frames,
            fps: self.animation.fps,
            start: self.animation.start,
            light_waves: self.light_waves,
            overlap: self.scene.render.overlap,
        }
    }

    /// Frames per second of the frames written (the GIF's and the video's).
    pub fn written_fps(&self) -> f32 {
        self.animation.fps / self.every.max(1) as f32
    }

    /// The frame numbers written, in order.
    pub fn frames_written(&self) -> impl Iterator<Item = u32> {
        (0..self.animation.frames).step_by(self.every.max(1) as usize)
    }

    /// Checks what can be checked without a GPU; one line per problem. The
    /// request's own settings are named as the command line gives them.
    pub fn validate(&self) -> Result<()> {
        self.render_settings()
            .check()
            .map_err(|e| Error::InvalidInput(format!("--{} {}", e.path, e.message)))?;
        if !(1..=MAX_FRAMES).contains(&self.every) {
            return Err(Error::InvalidInput(format!(
                "--every {} is not allowed, use 1..={MAX_FRAMES}",
                self.every
            )));
        }
        let written = self.frames_written().count();
        if self.light_waves && written < light_waves::LEAST_FRAMES {
            return Err(Error::InvalidInput(format!(
                "--light-waves measures a series of frames, and {written} would be written: \
                 ask for at least {} (e.g. --frames 24 --fps 8, a gust period or more)",
                light_waves::LEAST_FRAMES
            )));
        }
        if let Some(path) = &self.video {
            VideoFormat::of(path)?;
            video::check_size(self.width, self.height)?;
            video::find_ffmpeg()?;
        }
        self.scene.validate()?;
        self.scene.wind_grid()?;
        Ok(())
    }

    /// The names of every file this request writes into `out_dir`: its
    /// frames, the GIF, the report, the scene as rendered, and the video
    /// when it lies in that folder.
    pub fn outputs(&self, out_dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = self.frames_written().map(frame_name).collect();
        if self.gif && names.len() > 1 {
            names.push(GIF_NAME.into());
        }
        names.extend([REPORT_NAME.into(), SCENE_NAME.into()]);
        names.extend(
            self.video
                .as_deref()
                .and_then(|video| name_in_folder(out_dir, video)),
        );
        names
    }
}

/// Frame f's file name.
fn frame_name(f: u32) -> String {
    format!("frame_{f:04}.png")
}

/// Renders the request's frame into `out_dir`. On success (and when only
/// validation failed) `report.json` is written; a validation error still
/// returns `Err` after the report is on disk.
pub fn render_to_dir(request: &RenderRequest, out_dir: &Path) -> Result<RenderReport> {
    render_to_dir_observed(request, out_dir, &mut |_| true)
}

/// How far a render has got, for a progress display.
#[derive(Clone, Copy, Debug)]
pub struct FrameProgress {
    pub written: u32,
    pub planned: u32,
    /// Simulation steps still to run before the next frame (0 once a frame
    /// is written): a frame far ahead in simulated time is reached in
    /// submissions paced by `StepPace`, reported after each.
    pub steps_left: u64,
}

/// As `render_to_dir`, calling `observer` after each frame written, after
/// each batch of simulation steps before a frame and between a frame's
/// submissions (its steps, shadow and colour; `written` is then the
/// frames before it); when it returns false the render stops there
/// (Ctrl-C, SIGTERM), finishes the GIF with the frames so far and reports
/// itself interrupted.
pub fn render_to_dir_observed(
    request: &RenderRequest,
    out_dir: &Path,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<RenderReport> {
    let picture = Picture {
        view: request.view,
        dir: out_dir.to_path_buf(),
    };
    let mut reports = render_pictures(request, &[picture], observer)?;
    Ok(reports.remove(0))
}

/// One picture of each frame: how it is drawn and the folder it goes to.
#[derive(Clone, Debug)]
pub struct Picture {
    pub view: ViewMode,
    pub dir: PathBuf,
}

/// As `render_to_dir` for each picture: one simulation, each of its
/// frames drawn once per picture (the request's own `view` is not used).
/// Each picture's frames, GIF and scene go to its own folder as a render
/// of that view alone writes them, byte for byte, and so does its report
/// but for the times: the first picture's frame times include the
/// simulation's steps, and `wall_seconds` is the whole run's. A video is
/// written of one picture only: with several, the request may ask none.
pub fn render_pictures(
    request: &RenderRequest,
    pictures: &[Picture],
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<Vec<RenderReport>> {
    Ok(render_traced(request, pictures, None, observer)?.0)
}

/// As `render_pictures`, the simulation also traced as `trace` asks (its
/// scene the render's): the samples read as the render steps to its
/// frames, and after the last frame the steps on to the trace's end. The
/// frames and reports are those of `render_pictures` (the steps after the
/// last frame come after its report's counts); the trace is that of
/// `commands::trace::trace`, sample for sample. One simulation for both.
pub fn render_pictures_traced(
    request: &RenderRequest,
    pictures: &[Picture],
    trace: &TraceRequest,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<(Vec<RenderReport>, Trace)> {
    trace.validate()?;
    let (reports, trace) = render_traced(request, pictures, Some(trace), observer)?;
    Ok((reports, trace.expect("a trace asked for")))
}

fn render_traced(
    request: &RenderRequest,
    pictures: &[Picture],
    trace: Option<&TraceRequest>,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<(Vec<RenderReport>, Option<Trace>)> {
    if pictures.is_empty() || (pictures.len() > 1 && request.video.is_some()) {
        return Err(Error::InvalidInput(format!(
            "{} pictures of one render with {} video: one picture has a video, and a render at least one picture",
            pictures.len(),
            if request.video.is_some() { "a" } else { "no" }
        )));
    }
    request.validate()?;
    for picture in pictures {
        files::ensure_dir(&picture.dir)?;
    }
    if let Some(video) = &request.video {
        files::ensure_dir_of(video, "--video")?;
    }
    // Before any work: the files this run writes may replace only an
    // earlier run's (they go at the first frame).
    let claims = pictures
        .iter()
        .map(|p| OutputClaim::new(&p.dir, &request.outputs(&p.dir), request.overwrite))
        .collect::<Result<Vec<_>>>()?;
    // Room for the frames, each at least an eighth of its pixels' bytes.
    let frames = request.frames_written().count() as u64;
    for claim in &claims {
        claim.ensure_room(
            frames * files::least_png_bytes(request.width, request.height),
            &format!(
                "{frames} PNG frames of {} x {}",
                request.width, request.height
            ),
        )?;
    }
    let started = Instant::now();
    let ((mut reports, trace), validation) = on_gpu(&request.gpu, |gpu| {
        render_with(gpu, request, pictures, &claims, trace, observer)
    })?;
    let wall_seconds = started.elapsed().as_secs_f64();
    for ((report, picture), claim) in reports.iter_mut().zip(pictures).zip(&claims) {
        report.validation = validation.clone();
        report.wall_seconds = wall_seconds;
        let as_rendered = RenderRequest {
            view: picture.view,
            ..request.clone()
        };
        let scene = crate::scene::file::to_toml(&as_rendered.scene_as_rendered());
        claim.write(SCENE_NAME, scene.as_bytes())?;
        claim.write_json(REPORT_NAME, &*report)?;
    }
    validation.check()?;
    Ok((reports, trace))
}

fn render_with(
    gpu: &Gpu,
    request: &RenderRequest,
    pictures: &[Picture],
    claims: &[OutputClaim],
    trace: Option<&TraceRequest>,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<(Vec<RenderReport>, Option<Trace>)> {
    let scene = &request.scene;
    let warnings = preflight(gpu, request)?;
    let Planted {
        blades,
        under_obstacles,
        ..
    } = scene.planted()?;
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
    // The frames here are stepped in paced batches and drawn with breaks
    // for a stop: no frame's steps are sent ahead, so "auto" keeps one
    // submission (bench sends them ahead); "on" still runs the protocol.
    let mut scene = scene.clone();
    if scene.render.overlap == crate::scene::Overlap::Auto {
        scene.render.overlap = crate::scene::Overlap::Off;
    }
    let scene = &scene;
    let mut recorder = FrameRecorder::new(
        gpu,
        scene,
        (request.width, request.height),
        request.msaa,
        &blades,
        Some(&dynamic),
    )?;
    let mut sampler = match trace {
        Some(t) => Some(TraceSampler::new(
            t,
            &blades,
            &dynamic,
            recorder.simulation().expect("made with dynamics"),
        )?),
        None => None,
    };
    let (done, light_waves) = animate(
        gpu,
        request,
        &mut recorder,
        pictures,
        claims,
        sampler.as_mut(),
        observer,
    )?;
    let facts = RunFacts::of(gpu, &recorder, warnings, blades.len(), under_obstacles)?;
    let stopped = done.iter().any(|d| d.interrupted);
    let reports = pictures
        .iter()
        .zip(done)
        .map(|(picture, done)| report(gpu, request, picture, done, &facts, &light_waves))
        .collect();
    // The trace's steps after the last frame (none after a stop: the
    // trace ends at its last sample).
    let trace = match sampler {
        Some(mut sampler) => {
            let mut pace = StepPace::default();
            let mut done = facts.sim_steps;
            while !stopped && sampler.steps_to_next(done).is_some() {
                done += sampled_batch(gpu, &mut recorder, &mut pace, &mut sampler, u64::MAX)?;
            }
            Some(sampler.finish())
        }
        None => None,
    };
    Ok((reports, trace))
}

/// What is refused before anything is made (a wind grid the scene cannot
/// have, a frame the device cannot hold) and the warnings to report.
fn preflight(gpu: &Gpu, request: &RenderRequest) -> Result<Vec<String>> {
    let scene = &request.scene;
    let mut warnings = scene.wind_settings().check(&scene.wind_grid()?)?;
    if let Some(cover) = &scene.grass.cover {
        warnings.extend(crate::compute::cover_dynamics::far_poses_missing(
            gpu, cover,
        ));
    }
    crate::frame::check_fits(gpu, scene, request.width, request.height, request.msaa)?;
    Ok(warnings)
}

/// What one render learned beside its frames, the same for every picture
/// it drew.
struct RunFacts {
    warnings: Vec<String>,
    blades: usize,
    under_obstacles: usize,
    /// The patches' blades simulated (0 without their dynamics), and the
    /// cover's kept blades.
    patches: u64,
    simulated: u64,
    /// The cover's blades made, posed quasi-statically, posed from their
    /// state; its largest far and overall tip jumps.
    generated: u64,
    posed: u64,
    from_state: u64,
    tip_jumps: (f32, f32),
    msaa_used: u32,
    sim_dt: f32,
    substeps: u32,
    sim_steps: u64,
    angle_caps: CapCounts,
    /// The multigrid's pressure solves over the run (None with Jacobi or
    /// before a step).
    wind_solve: Option<SolveCounts>,
    untimed: Vec<(Phase, String)>,
}

impl RunFacts {
    /// What `recorder` learned after its last frame: its simulation's
    /// steps and angle caps (read back), the cover's counts.
    fn of(
        gpu: &Gpu,
        recorder: &FrameRecorder,
        warnings: Vec<String>,
        blades: usize,
        under_obstacles: usize,
    ) -> Result<Self> {
        let simulation = recorder.simulation().expect("made with dynamics");
        // A loss while reading back comes after the last frame.
        let after_the_frames = |e| match e {
            Error::DeviceLost { during } => Error::DeviceLost {
                during: format!("{during}, after the last frame (the frames are complete)"),
            },
            other => other,
        };
        let angle_caps = simulation
            .cap_counts(gpu, recorder.commands())
            .map_err(after_the_frames)?;
        let wind_solve = simulation
            .wind()
            .read_solve_counts(gpu, recorder.commands())
            .map_err(after_the_frames)?;
        Ok(Self {
            warnings,
            blades,
            under_obstacles,
            patches: if simulation.grass().is_some() {
                blades as u64
            } else {
                0
            },
            simulated: simulation
                .cover_dynamics()
                .map_or(0, |d| d.blade_count() as u64),
            generated: recorder.cover_blades(),
            posed: recorder.cover_posed(),
            from_state: recorder.cover_from_state(),
            tip_jumps: recorder.cover_tip_jumps(),
            msaa_used: recorder.samples(),
            sim_dt: simulation.dt(),
            substeps: simulation.substeps(),
            sim_steps: simulation.steps_done(),
            angle_caps,
            wind_solve,
            untimed: recorder.untimed_phases(),
        })
    }

    /// The blades made, simulated, posed, seen and drawn (`cull`: the
    /// cull pass's counts, None without it). A render always runs the
    /// wind: the cover's blades the frame may draw are posed in it.
    fn blade_counts(&self, cull: Option<&CullCounts>) -> BladeCounts {
        let all = self.patches + self.generated;
        let (in_view, drawn) = match cull {
            Some(c) => ((c.in_view + c.occluded) as u64, c.in_view as u64),
            None => (all, all),
        };
        BladeCounts {
            generated: self.generated,
            simulated: self.patches + self.simulated,
            quasi_static: self.posed,
            at_rest: self.generated - self.posed - self.from_state,
            in_view,
            drawn,
        }
    }
}

/// report.json of `picture`, drawn by the frame loop as `done` says.
fn report(
    gpu: &Gpu,
    request: &RenderRequest,
    picture: &Picture,
    done: Animated,
    facts: &RunFacts,
    light_waves: &Option<LightWaves>,
) -> RenderReport {
    let scene = &request.scene;
    let info = gpu.info();
    let covered = scene.grass.cover.is_some();
    let (far_jump, jump) = facts.tip_jumps;
    RenderReport {
        command_line: std::env::args().collect(),
        scene_file: SCENE_NAME.into(),
        shadow_map: scene.light.shadow_map,
        camera: scene.camera.clone(),
        scene: scene.name.clone(),
        seed: scene.seed,
        device: info.name.clone(),
        device_type: info.device_type.clone(),
        driver: info.driver.clone(),
        api_version: info.api_version.clone(),
        device_memory: gpu.device_memory(),
        msaa_requested: request.msaa,
        msaa_used: facts.msaa_used,
        blades: facts.blades,
        blade_counts: facts.blade_counts(done.cull.as_ref()),
        cover_largest_tip_jump_m: covered.then_some(jump),
        cover_largest_far_tip_jump_m: covered.then_some(far_jump),
        blades_under_obstacles: facts.under_obstacles,
        width: request.width,
        height: request.height,
        lod: scene.lod.enabled,
        tess_levels: scene.lod.levels,
        lod_distances: [scene.lod.close_distance, scene.lod.far_distance],
        view: picture.view,
        animation: request.animation,
        coupling: scene.wind.coupling,
        sim_dt: facts.sim_dt,
        substeps: facts.substeps,
        sim_steps: facts.sim_steps,
        angle_caps: facts.angle_caps,
        cap_fraction: facts.angle_caps.fraction(),
        wind_solve: facts.wind_solve,
        frames_planned: request.frames_written().count() as u32,
        frames: done.names,
        gif: done.gif,
        video: done.video,
        interrupted: done.interrupted,
        warnings: facts
            .warnings
            .iter()
            .cloned()
            .chain(legend::left_out(
                picture.view,
                scene.lod.levels,
                request.width,
                request.height,
            ))
            .collect(),
        pipeline_statistics: done.statistics,
        shadow_pipeline_statistics: done.shadow_statistics,
        cull: scene.cull.enabled,
        cull_counts: done.cull,
        timing: TimingSummary::of(&done.gpu_timings, &done.wall_ms, &facts.untimed),
        light_waves: light_waves.clone(),
        wall_seconds: 0.0,
        validation: ValidationReport::default(),
    }
}

/// The scene as rendered, beside the report.
const SCENE_NAME: &str = "scene.toml";
const REPORT_NAME: &str = "report.json";
