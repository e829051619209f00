//! The parts of one frame's recording (`FrameRecorder::record`): the
//! simulation's steps, the cover's tiles, what the passes draw, the colour
//! pass, the phase timer around each, and the breaks between a frame's
//! submissions. They use the layers below and the frame's timing phases.

use ash::vk;

use super::timing::Phase;
use crate::compute::{CoverTilePass, Simulation};
use crate::error::Result;
use crate::gpu::query::{Span, SpanTimer, StatisticsQuery};
use crate::gpu::{Access, Buffer, BufferUse, CommandPool, Recording};
use crate::render::cull::{BladeDraw, CullPass};
use crate::render::Renderer;
use crate::scene::cover::CoverTiles;
use crate::scene::Cover;

/// A break between a frame's submissions: what `rec` holds runs, then
/// `keep_going` says whether the frame goes on, in a new recording (None:
/// stop). Without `keep_going` the frame stays one submission. The timer's
/// spans and queries live in its pool, across submissions of one queue.
/// The frame's first submission waits for `waits` (the simulation's steps
/// beside the drawing, src/frame/ahead.rs), taken from it here.
pub(super) fn pause<'c>(
    commands: &'c CommandPool,
    rec: Recording<'c>,
    keep_going: &mut Option<&mut dyn FnMut() -> bool>,
    during: &str,
    waits: &mut Vec<vk::SemaphoreSubmitInfo<'static>>,
) -> Result<Option<Recording<'c>>> {
    let Some(go) = keep_going.as_mut() else {
        return Ok(Some(rec));
    };
    rec.submit_and_wait_with(during, &std::mem::take(waits), &[])?;
    if go() {
        commands.begin().map(Some)
    } else {
        Ok(None)
    }
}

/// What the colour and shadow passes draw of the blade `buffer` (its
/// `count` blades, or the cull pass's lists), its reads declared: both
/// passes' draws read the control points the grass step wrote, and the
/// cull pass's lists and draws.
pub(super) fn blade_draws<'a>(
    cull: Option<&'a CullPass>,
    rec: &Recording,
    buffer: &Buffer,
    count: u32,
) -> (BladeDraw<'a>, BladeDraw<'a>) {
    let mut drawn = vec![BufferUse::new(buffer, Access::VERTEX_INPUT)];
    if let Some(cull) = cull {
        drawn.extend(cull.drawn_uses());
    }
    rec.uses(&drawn);
    match cull {
        Some(c) => (
            BladeDraw::Listed(c.color_list()),
            BladeDraw::Listed(c.shadow_list()),
        ),
        None => (BladeDraw::All(count), BladeDraw::All(count)),
    }
}

/// A frame's `steps` of the simulation, the wind window first moved
/// under the camera at `camera_xz` (as part of the wind's work) where it
/// follows it.
pub(super) fn record_steps(
    simulation: &mut Simulation,
    rec: &Recording,
    t: &mut Timer,
    camera_xz: glam::Vec2,
    steps: u64,
) -> Result<()> {
    if simulation.wind().follows_camera() || simulation.cover_dynamics().is_some() {
        let mut followed = Ok(());
        t.span(rec, Phase::Wind, |rec| {
            followed = simulation.record_follow(rec, camera_xz);
        });
        followed?;
    }
    for _ in 0..steps {
        t.span(rec, Phase::Wind, |rec| simulation.record_wind_step(rec));
        t.span(rec, Phase::Grass, |rec| simulation.record_grass_step(rec));
    }
    Ok(())
}

/// The cover's tiles around the camera written into the blade buffer,
/// posed in the simulation's wind (`at`: the camera's x and z and the
/// frame's steps, whose time the far blades go towards their balance for).
pub(super) fn record_cover(
    pass: &mut CoverTilePass,
    cover: &Cover,
    simulation: Option<&Simulation>,
    rec: &Recording,
    t: &mut Timer,
    (camera_xz, steps): (glam::Vec2, u64),
) -> Result<()> {
    let tiles = CoverTiles::around(cover, camera_xz);
    if let Some(simulation) = simulation {
        pass.set_wind_grid(&simulation.wind().grid);
    }
    let kept = simulation
        .and_then(|s| s.cover_dynamics())
        .map(|d| *d.square());
    pass.set_dynamics(kept.as_ref(), camera_xz);
    pass.set_elapsed(simulation.map_or(0.0, |s| steps as f32 * s.dt()));
    let mut made = Ok(());
    t.span(rec, Phase::Cover, |rec| {
        made = pass.record(rec, &tiles);
    });
    made
}

/// The colour pass: the sky, ground and obstacles, then the grass (`draw`:
/// the blade buffer and which blades), its pipeline statistics counted.
/// Where a draw inside a pass cannot be timed (`timed` false), it is not
/// stamped (`untimed_phases` says why) rather than timed wrongly.
pub(super) fn record_color(
    renderer: &Renderer,
    statistics: &StatisticsQuery,
    rec: &Recording,
    t: &mut Timer,
    (buffer, draw): (&Buffer, BladeDraw),
    timed: bool,
) {
    statistics.reset(rec);
    let color = t.begin(rec, Phase::Color);
    renderer.begin_color(rec);
    let draw_grass = |rec: &Recording| {
        statistics.begin(rec);
        renderer.draw_grass(rec, buffer, draw);
        statistics.end(rec);
    };
    if timed {
        t.span(rec, Phase::GrassDraw, draw_grass);
    } else {
        draw_grass(rec);
    }
    renderer.end_color(rec);
    t.end(rec, color);
}

/// The phase timer where the device has one: spans around recorded work,
/// and the open span of the whole frame.
pub(super) struct Timer<'t>(
    pub(super) Option<&'t mut SpanTimer<Phase>>,
    pub(super) Option<Span>,
);

impl Timer<'_> {
    /// Closes the whole frame's span: the last thing before submitting.
    pub(super) fn end_frame(&mut self, rec: &Recording) {
        let frame = self.1.take();
        self.end(rec, frame);
    }

    pub(super) fn reset(&mut self, rec: &Recording) {
        if let Some(t) = self.0.as_deref_mut() {
            t.reset(rec);
        }
    }

    pub(super) fn begin(&mut self, rec: &Recording, phase: Phase) -> Option<Span> {
        self.0.as_deref_mut().map(|t| t.begin(rec, phase))
    }

    pub(super) fn end(&self, rec: &Recording, span: Option<Span>) {
        if let (Some(t), Some(span)) = (self.0.as_deref(), span) {
            t.end(rec, span);
        }
    }

    pub(super) fn span(&mut self, rec: &Recording, phase: Phase, work: impl FnOnce(&Recording)) {
        let span = self.begin(rec, phase);
        work(rec);
        self.end(rec, span);
    }
}
