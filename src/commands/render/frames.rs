//! The frame loop of `meadow render` (its parent, commands/render.rs,
//! plans the run and writes the reports): the simulation stepped up to
//! each written frame's time, in submissions paced to the machine (and
//! ending at a trace's samples), the frame drawn once per picture and
//! written as it is read back, the waves of light measured. It uses the
//! frame layer and report's writers; nothing here knows the command line.

use std::path::Path;
use std::time::Instant;

use super::{frame_name, FrameProgress, Picture, RenderRequest};
use crate::analysis::light_waves::{LightWaveSeries, LightWaves};
use crate::commands::trace::TraceSampler;
use crate::compute::StepPace;
use crate::error::{Error, Result};
use crate::frame::timing::FrameTimings;
use crate::frame::{CullCounts, Frame, FrameRecorder};
use crate::gpu::query::PipelineStatistics;
use crate::gpu::Gpu;
use crate::render::FrameUniforms;
use crate::report::claim::OutputClaim;
use crate::report::video::VideoWriter;
use crate::report::{files, legend};
use crate::scene::ViewMode;

/// What the frame loop got done.
#[derive(Default)]
pub(super) struct Animated {
    pub(super) names: Vec<String>,
    pub(super) gif: Option<String>,
    pub(super) video: Option<String>,
    pub(super) statistics: Option<PipelineStatistics>,
    pub(super) shadow_statistics: Option<PipelineStatistics>,
    pub(super) cull: Option<CullCounts>,
    pub(super) gpu_timings: Vec<Option<FrameTimings>>,
    pub(super) wall_ms: Vec<f64>,
    pub(super) interrupted: bool,
}

pub(super) const GIF_NAME: &str = "animation.gif";

/// One picture's frames as the frame loop writes them.
struct PictureWriter<'a> {
    view: ViewMode,
    dir: &'a Path,
    claim: &'a OutputClaim,
    gif: Option<files::GifWriter>,
    video: Option<VideoWriter>,
    done: Animated,
}

impl PictureWriter<'_> {
    /// Writes frame `f` (and adds it to the GIF and the video).
    fn write(&mut self, f: u32, frame: &Frame, wall_ms: f64) -> Result<()> {
        self.done.wall_ms.push(wall_ms);
        self.done.gpu_timings.push(frame.timings);
        let name = frame_name(f);
        files::write_png(&self.dir.join(&name), frame)?;
        self.claim.wrote(&name)?;
        if let Some(gif) = self.gif.as_mut() {
            gif.add(frame)?;
        }
        if let Some(video) = self.video.as_mut() {
            video.add(frame)?;
        }
        self.done.names.push(name);
        self.done.statistics = frame.statistics;
        self.done.shadow_statistics = frame.shadow_statistics;
        self.done.cull = frame.cull;
        Ok(())
    }

    /// Finishes the GIF and the video; a GIF or video of no frame is not
    /// written (dropping the writer removes its temporary file).
    fn finish(mut self, video_path: Option<&Path>) -> Result<Animated> {
        if let Some(gif) = self.gif.filter(|_| !self.done.names.is_empty()) {
            gif.finish()?;
            self.claim.wrote(GIF_NAME)?;
            self.done.gif = Some(GIF_NAME.to_string());
        }
        if let Some(writer) = self.video.filter(|_| !self.done.names.is_empty()) {
            writer.finish()?;
            if let Some(name) = video_path.and_then(|p| self.claim.name_in(p)) {
                self.claim.wrote(&name)?;
            }
            self.done.video = video_path.map(|p| p.display().to_string());
        }
        Ok(self.done)
    }
}

/// An error met while drawing frame `f`: a lost device says the frames
/// before it are complete.
fn at_frame(f: u32, e: Error) -> Error {
    match e {
        Error::DeviceLost { during } => Error::DeviceLost {
            during: format!("frame {f}, {during} (the frames before it are complete)"),
        },
        other => other,
    }
}

/// Each picture's writer, its folder claimed (what an earlier render
/// wrote there goes, so the folder never mixes two runs; a run refused
/// before this point leaves the old outputs alone), its GIF and video
/// begun.
fn open_writers<'a>(
    request: &RenderRequest,
    pictures: &'a [Picture],
    claims: &'a [OutputClaim],
    planned: u32,
) -> Result<Vec<PictureWriter<'a>>> {
    let mut writers = Vec::with_capacity(pictures.len());
    for (picture, claim) in pictures.iter().zip(claims) {
        claim.begin()?;
        let gif = if request.gif && planned > 1 {
            let seconds = 1.0 / request.written_fps();
            Some(files::GifWriter::create(
                &picture.dir.join(GIF_NAME),
                seconds,
            )?)
        } else {
            None
        };
        // Only the first picture has the video (`render_pictures` allows
        // one only with a single picture).
        let video = match (&request.video, writers.is_empty()) {
            (Some(path), true) => Some(VideoWriter::create(
                path,
                request.width,
                request.height,
                request.written_fps(),
            )?),
            _ => None,
        };
        writers.push(PictureWriter {
            view: picture.view,
            dir: &picture.dir,
            claim,
            gif,
            video,
            done: Animated::default(),
        });
    }
    Ok(writers)
}

/// The shaded frame at `time` (drawn unless a picture already was) and
/// its data view, for the waves of light; `steps` go with the first
/// drawn. None: stopped.
fn light_wave_frames(
    gpu: &Gpu,
    request: &RenderRequest,
    recorder: &mut FrameRecorder,
    time: f64,
    shaded: Option<Vec<u8>>,
    steps: &mut u64,
) -> Result<Option<(Vec<u8>, Vec<u8>)>> {
    let base = FrameUniforms::new(
        &request.scene,
        request.width,
        request.height,
        ViewMode::Shaded,
        time as f32,
    );
    let mut draw = |uniforms: &FrameUniforms| {
        recorder.render_unless_stopped(gpu, uniforms, std::mem::take(steps), None)
    };
    let shaded = match shaded {
        Some(rgba) => Some(rgba),
        None => draw(&base)?.map(|frame| frame.rgba),
    };
    let data = draw(&base.displacement_view())?;
    Ok(shaded.zip(data.map(|d| d.rgba)))
}

/// Steps toward a frame far ahead in submissions paced to the machine,
/// a stop asked after each (`progress` with the steps left); leaves the
/// last batch in `steps`, to go with the frame, timed as its own. False:
/// stopped.
///
/// With a trace (`sampler`) every step runs here, the frame's own too, in
/// submissions that end at the trace's samples.
fn step_towards(
    gpu: &Gpu,
    recorder: &mut FrameRecorder,
    pace: &mut StepPace,
    steps: &mut u64,
    mut sampler: Option<&mut TraceSampler>,
    progress: FrameProgress,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<bool> {
    let leave = |steps: u64, pace: &StepPace, traced: bool| {
        if traced {
            0
        } else {
            pace.next(steps)
        }
    };
    while *steps > leave(*steps, pace, sampler.is_some()) {
        *steps -= match sampler.as_deref_mut() {
            Some(sampler) => sampled_batch(gpu, recorder, pace, sampler, *steps)?,
            None => pace.run(*steps, |batch| recorder.simulate(batch))?,
        };
        let progress = FrameProgress {
            steps_left: *steps,
            ..progress
        };
        if !observer(progress) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// One written frame: its number, its simulated time, and whether its
/// shaded picture is kept for the waves of light.
#[derive(Clone, Copy)]
struct FrameAt {
    f: u32,
    time: f64,
    keep_shaded: bool,
}

/// Draws `frame` once per picture and writes it; the `steps` go with the
/// first picture, the others draw the same instant, and between the
/// submissions `keep_going` is asked. Returns the shaded picture's pixels
/// where asked to keep them, or None where stopped.
fn draw_pictures(
    gpu: &Gpu,
    request: &RenderRequest,
    recorder: &mut FrameRecorder,
    writers: &mut [PictureWriter],
    frame: FrameAt,
    steps: &mut u64,
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<Option<Option<Vec<u8>>>> {
    let mut shaded: Option<Vec<u8>> = None;
    for writer in writers.iter_mut() {
        let uniforms = FrameUniforms::new(
            &request.scene,
            request.width,
            request.height,
            writer.view,
            frame.time as f32,
        );
        let started = Instant::now();
        let drawn = recorder.render_unless_stopped(
            gpu,
            &uniforms,
            std::mem::take(steps),
            Some(&mut *keep_going),
        )?;
        let Some(mut drawn) = drawn else {
            return Ok(None);
        };
        legend::stamp(&mut drawn, writer.view, request.scene.lod.levels);
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        writer.write(frame.f, &drawn, wall_ms)?;
        if frame.keep_shaded && writer.view == ViewMode::Shaded && shaded.is_none() {
            shaded = Some(drawn.rgba);
        }
    }
    Ok(Some(shaded))
}

/// One submission of at most `steps` steps (paced to the machine) that
/// ends at the trace's next sample if that comes sooner, the samples due
/// before and after it taken; the steps run.
pub(super) fn sampled_batch(
    gpu: &Gpu,
    recorder: &mut FrameRecorder,
    pace: &mut StepPace,
    sampler: &mut TraceSampler,
    steps: u64,
) -> Result<u64> {
    let mut take_due = |recorder: &FrameRecorder| -> Result<Option<u64>> {
        let simulation = recorder.simulation().expect("made with dynamics");
        let done = simulation.steps_done();
        sampler.sample_if_due(
            gpu,
            recorder.commands(),
            simulation,
            recorder.blades(),
            done,
        )?;
        Ok(sampler.steps_to_next(done))
    };
    let next = take_due(recorder)?;
    if next == Some(0) {
        return Err(Error::InvalidInput(
            "a trace's sample was stepped past (an internal fault: please report it)".into(),
        ));
    }
    if steps == 0 {
        return Ok(0);
    }
    let ran = pace.run(steps.min(next.unwrap_or(u64::MAX)), |batch| {
        recorder.simulate(batch)
    })?;
    take_due(recorder)?;
    Ok(ran)
}

/// Simulates up to each written frame's time and renders it once per
/// picture, in one submission per picture (the first also steps the
/// simulation); writes each frame (and adds it to the GIF) as it is read
/// back. With `light_waves`, each instant is drawn once more in the data
/// view (and shaded, when no picture is) and measured. A failure names the
/// frame it happened at; the frames written before it stay complete.
pub(super) fn animate(
    gpu: &Gpu,
    request: &RenderRequest,
    recorder: &mut FrameRecorder,
    pictures: &[Picture],
    claims: &[OutputClaim],
    sampler: Option<&mut TraceSampler>,
    observer: &mut dyn FnMut(FrameProgress) -> bool,
) -> Result<(Vec<Animated>, Option<LightWaves>)> {
    let planned = request.frames_written().count() as u32;
    let mut frames = FrameLoop {
        gpu,
        request,
        recorder,
        writers: open_writers(request, pictures, claims, planned)?,
        pace: StepPace::default(),
        sampler,
        waves: request
            .light_waves
            .then(|| LightWaveSeries::new(request.width, request.height)),
        observer,
        planned,
    };
    let mut interrupted = false;
    for (written, f) in request.frames_written().enumerate() {
        if !frames.frame(written as u32, f)? {
            interrupted = true;
            break;
        }
    }
    let FrameLoop { writers, waves, .. } = frames;
    let done = writers
        .into_iter()
        .map(|w| {
            let mut done = w.finish(request.video.as_deref())?;
            done.interrupted = interrupted;
            Ok(done)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((done, waves.and_then(|w| w.measure())))
}

/// What the frame loop carries from one written frame to the next.
struct FrameLoop<'a, 'r> {
    gpu: &'a Gpu,
    request: &'a RenderRequest,
    recorder: &'a mut FrameRecorder,
    writers: Vec<PictureWriter<'a>>,
    pace: StepPace,
    sampler: Option<&'r mut TraceSampler>,
    waves: Option<LightWaveSeries>,
    observer: &'a mut dyn FnMut(FrameProgress) -> bool,
    planned: u32,
}

impl FrameLoop<'_, '_> {
    /// Frame `f`, the `written`-th written: stepped to, drawn in every
    /// picture, measured for the waves of light. False: stopped.
    fn frame(&mut self, written: u32, f: u32) -> Result<bool> {
        let (gpu, request, planned) = (self.gpu, self.request, self.planned);
        let at_frame = |e| at_frame(f, e);
        let time = request.animation.time_of(f);
        let mut steps = self.recorder.steps_until(time)?;
        let progress = FrameProgress {
            written,
            planned,
            steps_left: 0,
        };
        let stepped = step_towards(
            gpu,
            self.recorder,
            &mut self.pace,
            &mut steps,
            self.sampler.as_deref_mut(),
            progress,
            self.observer,
        );
        if !stepped.map_err(at_frame)? {
            return Ok(false);
        }
        let frame = FrameAt {
            f,
            time,
            keep_shaded: self.waves.is_some(),
        };
        let observer = &mut *self.observer;
        let drawn = draw_pictures(
            gpu,
            request,
            self.recorder,
            &mut self.writers,
            frame,
            &mut steps,
            &mut || observer(progress),
        )
        .map_err(at_frame)?;
        let Some(shaded) = drawn else {
            return Ok(false);
        };
        if let Some(series) = self.waves.as_mut() {
            let drawn = light_wave_frames(gpu, request, self.recorder, time, shaded, &mut steps)
                .map_err(at_frame)?;
            let Some((shaded, data)) = drawn else {
                return Ok(false);
            };
            series.add(time, &shaded, &data);
        }
        let progress = FrameProgress {
            written: written + 1,
            planned,
            steps_left: 0,
        };
        Ok((self.observer)(progress) || progress.written == planned)
    }
}
