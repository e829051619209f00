//! One frame, both of the paper's phases: the blade buffer they share, and
//! the frame recorder, which owns the command buffer, the phase timer and
//! the pipeline-statistics query, and records, in one submission:
//!
//! simulate (wind step, grass step) x steps -> cull -> shadow pass ->
//! colour pass (sky, ground, grass) -> depth pyramid -> read-back.
//!
//! With `render.overlap` the steps go instead in a submission of their own
//! beside the drawing of the frame before (`ahead.rs`).
//!
//! The simulating and rendering phases do not know each other; this is the
//! one place that puts them in order. Its children: `blades.rs` (the
//! blade buffer), `record.rs` (the parts of a frame's recording: the
//! steps, the cover, the passes' draws, the colour pass, the timer and the
//! breaks between submissions), `ahead.rs` (the simulation beside the
//! drawing), `timing.rs` (the phases' timing).

mod ahead;
pub mod blades;
mod record;
pub mod timing;

use crate::compute::cover_tiles::{CoverSetup, CoverWind};
use crate::compute::{CoverTilePass, Simulation};
use crate::error::{Error, Result};
use crate::gpu::query::{PipelineStatistics, SpanTimer, StatisticsQuery};
use crate::gpu::swapchain::Presented;
use crate::gpu::{CommandPool, Gpu, OverlayDraw, OverlayRenderer, Recording, Swapchain};
use crate::model::collider::Collider;
use crate::model::{Blade, GrassBlade};
use crate::render::canopy_map::CanopyMap;
use crate::render::cull::CullPass;
use crate::render::depth_pyramid::Occluders;
use crate::render::terrain;
use crate::render::{FrameUniforms, Renderer};
use crate::scene::cover::CoverTiles;
use crate::scene::{Cover, Overlap, Scene, ViewMode};
use ahead::Ahead;
use ash::vk;
use record::{blade_draws, pause, record_color, record_cover, record_steps, Timer};

pub use crate::render::cull::CullCounts;
pub use blades::BladeBuffer;
use timing::{FrameTimings, Phase};

/// Which moments of the simulation become frames: frame f shows simulated
/// time `start + f / fps` (seconds). The simulation starts at rest at time
/// 0 and advances in the scene's fixed steps, whatever the frame rate.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Animation {
    pub frames: u32,
    pub fps: f32,
    pub start: f32,
}

impl Default for Animation {
    fn default() -> Self {
        Self {
            frames: 1,
            fps: 30.0,
            start: 0.0,
        }
    }
}

impl Animation {
    pub fn time_of(&self, frame: u32) -> f64 {
        self.start as f64 + frame as f64 / self.fps as f64
    }
}

/// A finished frame on the host.
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, sRGB-encoded, rows top to bottom.
    pub rgba: Vec<u8>,
    /// Counters of the colour pass's grass draw alone (None where
    /// unsupported).
    pub statistics: Option<PipelineStatistics>,
    /// The same for the shadow pass (blades and obstacles; only the blades
    /// are tessellated); None without shadows.
    pub shadow_statistics: Option<PipelineStatistics>,
    /// GPU time of each phase (None where the device has no timestamps).
    pub timings: Option<FrameTimings>,
    /// How many blades each pass drew (None with culling off: all).
    pub cull: Option<CullCounts>,
}

/// What a frame needs: the blades, the simulating phase (none for a still
/// of blades at rest), the rendering phase, and the recording of both.
pub struct FrameRecorder {
    /// With `render.overlap`: the steps' submissions beside the drawing.
    ahead: Option<Ahead>,
    simulation: Option<Simulation>,
    /// With `[grass.cover]`: the pass making its tiles around the camera
    /// each frame, after the patches' blades, and the cover.
    cover: Option<(CoverTilePass, Cover)>,
    /// Where the camera stands this frame (x, z): what the cover's tiles
    /// surround.
    camera_xz: glam::Vec2,
    cull: Option<CullPass>,
    renderer: Renderer,
    blades: BladeBuffer,
    statistics: StatisticsQuery,
    shadow_statistics: StatisticsQuery,
    timer: Option<SpanTimer<Phase>>,
    commands: CommandPool,
    extent: (u32, u32),
    /// Why this device cannot time the grass draw inside the colour pass
    /// (`DeviceInfo::draw_timing_unavailable`); None where it can.
    draw_timing_unavailable: Option<String>,
    /// A cover on terrain: its mesh follows the camera.
    ground_follow: Option<GroundFollow>,
    /// The largest move (m) of a cover blade's tip between two frames
    /// since the recorder was made: over the blades posed quasi-statically,
    /// and over all.
    cover_tip_jumps: (f32, f32),
}

/// A cover's ground over terrain: the terrain mesh remade about the
/// camera as it moves (`terrain::mesh_centre`), from the scene it was
/// made for.
struct GroundFollow {
    scene: Box<Scene>,
    /// The centre the renderer's mesh was made about.
    centre: [f32; 2],
}

impl FrameRecorder {
    /// A `width` x `height` view with up to `msaa` samples of `blades` as
    /// `scene` lights them; with `dynamics` (one per blade) they move in
    /// the scene's wind, else they stay at rest.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        (width, height): (u32, u32),
        msaa: u32,
        blades: &[Blade],
        dynamics: Option<&[GrassBlade]>,
    ) -> Result<Self> {
        // Refused before anything is made.
        let overlap = overlaps(gpu, scene, dynamics.is_some())?;
        let commands = CommandPool::new(gpu, "frame commands")?;
        let (eye, _) = scene.camera.at(0.0);
        let renderer = Self::new_renderer(
            gpu,
            &commands,
            scene,
            eye,
            &scene.colliders,
            (width, height),
            msaa,
        )?;
        let statistics = StatisticsQuery::new(gpu, "grass pipeline statistics")?;
        let shadow_statistics = StatisticsQuery::new(gpu, "shadow pass pipeline statistics")?;
        let timer = SpanTimer::new(gpu, 16, "frame phase timestamps")?;
        let room = match &scene.grass.cover {
            Some(c) => u32::try_from(crate::scene::cover::most_blades(c)).map_err(|_| {
                Error::InvalidInput(
                    "grass.cover makes more blades than one buffer indexes; lower density or view_distance".into(),
                )
            })?,
            None => 0,
        };
        let blade_buffer = BladeBuffer::with_room(gpu, &commands, blades, room)?;
        let ahead = match overlap {
            true => Some(Ahead::new(
                gpu,
                BladeBuffer::simulated_twin(gpu, &commands, blades)?,
            )?),
            false => None,
        };
        // Beside the drawing the steps write blades of their own.
        let written = ahead
            .as_ref()
            .map_or(blade_buffer.buffer(), Ahead::simulated_blades);
        let simulation = dynamics
            .map(|d| Simulation::new(gpu, &commands, scene, d, written))
            .transpose()?;
        let cover = Self::cover_pass(
            gpu,
            &commands,
            scene,
            simulation.as_ref(),
            &renderer,
            &blade_buffer,
            blades.len() as u32,
        )?;
        let cull = Self::cull_pass(gpu, scene, &renderer, &blade_buffer)?;
        Ok(Self {
            ahead,
            simulation,
            cover,
            camera_xz: glam::Vec2::ZERO,
            cull,
            renderer,
            blades: blade_buffer,
            statistics,
            shadow_statistics,
            timer,
            commands,
            extent: (width, height),
            draw_timing_unavailable: gpu.info().draw_timing_unavailable.clone(),
            ground_follow: scene.cover_on_terrain().then(|| GroundFollow {
                scene: Box::new(scene.clone()),
                centre: terrain::mesh_centre(scene, eye),
            }),
            cover_tip_jumps: (0.0, 0.0),
        })
    }

    /// Renders at `width` x `height` from now on (a window resized): new
    /// render targets, and a cull pass reading the new frame uniforms. The
    /// blades and the simulation carry on as they were.
    pub fn resize(&mut self, gpu: &Gpu, scene: &Scene, (width, height): (u32, u32)) -> Result<()> {
        if (width, height) == self.extent {
            return Ok(());
        }
        let msaa = self.renderer.samples();
        // The cull pass's set names the old renderer's uniforms: it goes first.
        self.cull = None;
        // The colliders drawn carry over (`set_colliders` may have changed
        // the scene's).
        let colliders = self.renderer.colliders().to_vec();
        // The terrain mesh about where the camera starts; the next frame
        // moves it under the camera if it is elsewhere.
        let (eye, _) = scene.camera.at(0.0);
        self.renderer = Self::new_renderer(
            gpu,
            &self.commands,
            scene,
            eye,
            &colliders,
            (width, height),
            msaa,
        )?;
        if let Some(follow) = &mut self.ground_follow {
            follow.centre = terrain::mesh_centre(scene, eye);
        }
        self.cull = Self::cull_pass(gpu, scene, &self.renderer, &self.blades)?;
        // The cover's pass reads the new renderer's uniforms too.
        if let Some((pass, _)) = &self.cover {
            let base = pass.base();
            self.cover = None;
            self.cover = Self::cover_pass(
                gpu,
                &self.commands,
                scene,
                self.simulation.as_ref(),
                &self.renderer,
                &self.blades,
                base,
            )?;
        }
        self.extent = (width, height);
        Ok(())
    }

    fn new_renderer(
        gpu: &Gpu,
        commands: &CommandPool,
        scene: &Scene,
        eye: glam::Vec3,
        colliders: &[Collider],
        (width, height): (u32, u32),
        msaa: u32,
    ) -> Result<Renderer> {
        Renderer::new(
            gpu,
            commands,
            (width, height),
            msaa,
            scene.light.shadow_map,
            &scene.wind.obstacles,
            colliders,
            terrain::mesh(scene, eye).as_ref(),
            &CanopyMap::of(scene),
            scene.cull.enabled && scene.cull.occlusion,
        )
    }

    /// With `[grass.cover]`, its tile pass after the patches' `base`
    /// blades: posed in the simulation's wind (only the blades the frame
    /// may draw), at rest in a still.
    fn cover_pass(
        gpu: &Gpu,
        commands: &CommandPool,
        scene: &Scene,
        simulation: Option<&Simulation>,
        renderer: &Renderer,
        blades: &BladeBuffer,
        base: u32,
    ) -> Result<Option<(CoverTilePass, Cover)>> {
        let Some(cover) = &scene.grass.cover else {
            return Ok(None);
        };
        let input = simulation.map(|s| s.wind().grass_input());
        let setup = CoverSetup {
            cover,
            seed: cover.seed.unwrap_or(scene.seed),
            grass: &scene.grass,
            vertices: blades.buffer(),
            base,
            wind: input.as_ref().map(|i| CoverWind {
                velocity: i.velocity,
                grid: i.grid,
            }),
            frame: renderer.uniforms(),
            pose_drawn_only: true,
            states: simulation
                .and_then(Simulation::cover_dynamics)
                .map(|d| d.states()),
            presses: simulation
                .and_then(Simulation::cover_dynamics)
                .and_then(|d| d.presses()),
            terrain: &scene.ground.terrain(),
            far_poses: simulation
                .and_then(Simulation::cover_dynamics)
                .and_then(|d| d.far_poses()),
        };
        let pass = CoverTilePass::new(gpu, commands, setup)?;
        Ok(Some((pass, cover.clone())))
    }

    fn cull_pass(
        gpu: &Gpu,
        scene: &Scene,
        renderer: &Renderer,
        blades: &BladeBuffer,
    ) -> Result<Option<CullPass>> {
        scene
            .cull
            .enabled
            .then(|| {
                CullPass::new(
                    gpu,
                    renderer.uniforms(),
                    blades.buffer(),
                    blades.count(),
                    renderer.shadows(),
                    scene.cull.edge_on,
                    renderer.depth_pyramid().map(|p| p.buffer()),
                )
            })
            .transpose()
    }

    /// The phases this device cannot time, with why: the grass draw where
    /// a draw inside a pass cannot be timed (the colour pass as a whole
    /// still is).
    pub fn untimed_phases(&self) -> Vec<(Phase, String)> {
        self.draw_timing_unavailable
            .iter()
            .map(|why| (Phase::GrassDraw, why.clone()))
            .collect()
    }

    /// The MSAA sample count actually used.
    pub fn samples(&self) -> u32 {
        self.renderer.samples()
    }

    pub fn simulation(&self) -> Option<&Simulation> {
        self.simulation.as_ref()
    }

    /// Changes what drives the wind from the next step on
    /// (`WindPass::set_drive`): the viewer's wind keys and gusts.
    pub fn set_wind_drive(
        &mut self,
        gpu: &Gpu,
        inflow: Option<crate::model::wind::Inflow>,
        sources: &[crate::model::wind::WindSource],
    ) -> Result<()> {
        // Steps in flight read the drive: it changes after them.
        if let Some(ahead) = &self.ahead {
            ahead.settle()?;
        }
        match self.simulation.as_mut() {
            Some(s) => s.wind_mut().set_drive(gpu, &self.commands, inflow, sources),
            None => Err(Error::InvalidInput(
                "blades at rest have no wind to change".into(),
            )),
        }
    }

    /// The colliders from the next frame on, pressing the grass, pushing
    /// the air and drawn (the viewer's ball). A recorder made without
    /// colliders, or without dynamics, refuses any. Their motion goes to
    /// the GPU in the next frame's command buffer; only new shapes upload
    /// (and wait for) meshes.
    pub fn set_colliders(&mut self, gpu: &Gpu, colliders: &[Collider]) -> Result<()> {
        match self.simulation.as_mut() {
            Some(s) => s.set_colliders(colliders)?,
            None if colliders.is_empty() => {}
            None => {
                return Err(Error::InvalidInput(
                    "blades at rest cannot be pressed by colliders".into(),
                ))
            }
        }
        self.renderer.set_colliders(gpu, &self.commands, colliders)
    }

    /// The colliders drawn and simulated now.
    pub fn colliders(&self) -> &[Collider] {
        self.renderer.colliders()
    }

    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// The cover's blades each frame makes around the camera (0 without
    /// `[grass.cover]`): its whole square of tiles, less those the last
    /// frame (run and waited for) left out beyond the cover's bounds.
    pub fn cover_blades(&self) -> u64 {
        self.cover.as_ref().map_or(0, |(p, c)| {
            CoverTiles::around(c, self.camera_xz)
                .blade_count()
                .saturating_sub(p.outside() as u64)
        })
    }

    /// Of those, how many the last frame posed quasi-statically (the ones
    /// it may draw beyond the simulated square; the others stand at rest
    /// or take their state).
    pub fn cover_posed(&self) -> u64 {
        self.cover.as_ref().map_or(0, |(p, _)| p.posed() as u64)
    }

    /// Of those, how many the last frame posed from their dynamics' state
    /// (the simulated square's tiles).
    pub fn cover_from_state(&self) -> u64 {
        self.cover
            .as_ref()
            .map_or(0, |(p, _)| p.from_state() as u64)
    }

    /// The largest move (m) of a cover blade's tip from one frame to the
    /// next, over every pair of frames this recorder drew: over the blades
    /// posed quasi-statically (the far field), and over
    /// every posed blade (those from their dynamics' state too). A blade
    /// counts where both frames posed it. (0, 0) without a cover.
    pub fn cover_tip_jumps(&self) -> (f32, f32) {
        self.cover_tip_jumps
    }

    /// The cull pass (None with culling off).
    pub fn cull(&self) -> Option<&CullPass> {
        self.cull.as_ref()
    }

    pub fn blades(&self) -> &BladeBuffer {
        &self.blades
    }

    pub fn commands(&self) -> &CommandPool {
        &self.commands
    }

    /// Simulation steps needed to reach `time` (0 without a simulation).
    pub fn steps_until(&self, time: f64) -> Result<u64> {
        self.simulation
            .as_ref()
            .map_or(Ok(0), |s| s.steps_until(time))
    }

    /// Runs `steps` simulation steps in one submission of their own, ahead
    /// of a frame far ahead in simulated time (untimed; the frame's own
    /// submission times the steps it records).
    pub fn simulate(&mut self, steps: u64) -> Result<()> {
        let Some(simulation) = self.simulation.as_mut() else {
            return Err(Error::InvalidInput(
                "a still of blades at rest cannot be simulated".into(),
            ));
        };
        // The last frame's depth shows the blades where they were.
        self.renderer.forget_depth();
        if let Some(ahead) = self.ahead.as_mut() {
            // The same submission as a frame's steps, untimed and waited for.
            ahead.submit(None, simulation, self.blades.buffer(), steps)?;
            ahead.take(steps)?;
            return ahead.settle();
        }
        let rec = self.commands.begin()?;
        simulation.record_steps(&rec, steps);
        rec.submit_and_wait("simulating ahead of a frame")
    }

    /// Whether the steps run beside the drawing (`render.overlap`), and
    /// where: on a queue of their own, or in order on the one queue.
    pub fn overlap(&self) -> &'static str {
        match &self.ahead {
            None => "off",
            Some(a) if a.own_queue() => "two queues",
            Some(_) => "one queue",
        }
    }

    /// As `render`, and after this frame's drawing is submitted, the next
    /// frame's `next_steps` steps go to the GPU beside it (with
    /// `render.overlap`; without, they wait for the next `render`). The
    /// next frame must ask for as many.
    pub fn render_then(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
        next_steps: u64,
    ) -> Result<Frame> {
        let drawn = self.draw(gpu, uniforms, steps, None, next_steps)?;
        drawn.ok_or_else(|| Error::InvalidInput("a frame without breaks cannot stop".into()))
    }

    /// Records `steps` simulation steps and then the frame into one command
    /// buffer, submits it and reads the frame back.
    pub fn render(&mut self, gpu: &Gpu, uniforms: &FrameUniforms, steps: u64) -> Result<Frame> {
        self.render_then(gpu, uniforms, steps, 0)
    }

    /// As `render`, but with `keep_going` the frame goes to the GPU in
    /// three submissions (its steps, the cull and shadow passes, the colour
    /// pass and read-back) and `keep_going` is asked between them: a stop
    /// waits for one of them, not the whole frame. On false the frame is
    /// left undrawn (None); the steps already run stay run.
    pub fn render_unless_stopped(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
        keep_going: Option<&mut dyn FnMut() -> bool>,
    ) -> Result<Option<Frame>> {
        self.draw(gpu, uniforms, steps, keep_going, 0)
    }

    /// A frame read back, and the next frame's steps submitted beside it.
    fn draw(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
        keep_going: Option<&mut dyn FnMut() -> bool>,
        next_steps: u64,
    ) -> Result<Option<Frame>> {
        let end = |rec: Recording<'_>, renderer: &Renderer, t: &mut Timer<'_>, sync: Sync<'_>| {
            t.span(&rec, Phase::Readback, |rec| renderer.record_readback(rec));
            t.end_frame(&rec);
            rec.submit("rendering a frame", sync.0, sync.1)
        };
        let drawn = self.record(gpu, uniforms, (steps, next_steps), keep_going, end)?;
        Ok(drawn.map(|((), stats)| Frame {
            width: self.extent.0,
            height: self.extent.1,
            rgba: self.renderer.pixels(),
            statistics: stats.statistics,
            shadow_statistics: stats.shadow_statistics,
            timings: stats.timings,
            cull: stats.cull,
        }))
    }

    /// As `render`, but the frame goes to image `index` of a window's
    /// swapchain (blitted, scaled to the window, the viewer's overlay drawn
    /// over it) instead of the host. The blit and the overlay are recorded
    /// after the frame's timed span closes: they are the window's cost,
    /// not the frame's.
    pub fn present(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
        swapchain: &Swapchain,
        index: u32,
        overlay: Option<(&mut OverlayRenderer, &OverlayDraw)>,
    ) -> Result<(Presented, FrameStats)> {
        if self.ahead.is_some() {
            return Err(Error::InvalidInput(
                "a window shows frames with render.overlap = \"off\"".into(),
            ));
        }
        let shown = self.record(gpu, uniforms, (steps, 0), None, |rec, renderer, t, _| {
            t.span(&rec, Phase::Readback, |rec| {
                renderer.record_present_source(rec)
            });
            t.end_frame(&rec);
            let frame = renderer.targets().final_image();
            swapchain.blit_and_present(rec, frame, index, overlay, "showing a frame")
        })?;
        shown.ok_or_else(|| Error::InvalidInput("a frame without breaks cannot stop".into()))
    }

    /// Records the steps and the frame's passes, then hands the recording
    /// to `end` (which records the frame's way out, closes the frame span
    /// and submits, waiting for and signalling `Sync`), waits for it and
    /// reads the frame's counters. With `keep_going` the steps and the
    /// shadow go to the GPU on their own first, each asking it afterwards
    /// (None: it said stop, the frame is not drawn). Beside the drawing,
    /// the steps go in their own submission (`ahead.rs`), and the next
    /// frame's (`steps.1`) after this frame's drawing.
    fn record<T>(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        (steps, next_steps): (u64, u64),
        mut keep_going: Option<&mut dyn FnMut() -> bool>,
        end: impl FnOnce(Recording<'_>, &Renderer, &mut Timer<'_>, Sync<'_>) -> Result<T>,
    ) -> Result<Option<(T, FrameStats)>> {
        let occluders = self.prepare(gpu, uniforms, steps)?;
        let Self {
            ahead,
            simulation,
            cover,
            camera_xz,
            cull,
            renderer,
            blades,
            statistics,
            shadow_statistics,
            timer,
            commands,
            draw_timing_unavailable,
            ..
        } = self;
        let (buffer, count) = (blades.buffer(), blades.count());
        let mut waits = Vec::new();
        if let (Some(ahead), Some(simulation)) = (ahead.as_mut(), simulation.as_mut()) {
            if ahead.in_flight().is_none() && steps > 0 {
                ahead.submit(Some(gpu), simulation, buffer, steps)?;
            }
            ahead.take(steps)?;
            if steps > 0 {
                if let Some(go) = keep_going.as_mut() {
                    ahead.settle()?;
                    if !go() {
                        renderer.end_frame(false);
                        return Ok(None);
                    }
                }
            }
            waits = ahead.waits();
        }
        let mut rec = commands.begin()?;
        let mut t = Timer(timer.as_mut(), None);
        t.reset(&rec);
        t.1 = t.begin(&rec, Phase::Frame);
        if let (None, Some(simulation)) = (ahead.as_ref(), simulation.as_mut()) {
            record_steps(simulation, &rec, &mut t, *camera_xz, steps)?;
            if steps > 0 {
                let during = "simulating a frame's steps";
                match pause(commands, rec, &mut keep_going, during, &mut waits)? {
                    Some(next) => rec = next,
                    None => {
                        renderer.end_frame(false);
                        return Ok(None);
                    }
                }
            }
        }
        if let Some((pass, cover)) = cover.as_mut() {
            let at = (*camera_xz, steps);
            record_cover(pass, cover, simulation.as_ref(), &rec, &mut t, at)?;
        }
        if let Some(cull) = cull.as_ref() {
            t.span(&rec, Phase::Cull, |rec| cull.record(rec, occluders));
        }
        let (color_draw, shadow_draw) = blade_draws(cull.as_ref(), &rec, buffer, count);
        shadow_statistics.reset(&rec);
        t.span(&rec, Phase::Shadow, |rec| {
            shadow_statistics.begin(rec);
            renderer.record_shadow(rec, buffer, shadow_draw);
            shadow_statistics.end(rec);
        });
        let during = "drawing a frame's shadow";
        match pause(commands, rec, &mut keep_going, during, &mut waits)? {
            Some(next) => rec = next,
            None => {
                renderer.end_frame(false);
                return Ok(None);
            }
        }
        let timed = draw_timing_unavailable.is_none();
        record_color(
            renderer,
            statistics,
            &rec,
            &mut t,
            (buffer, color_draw),
            timed,
        );
        // The pyramid's build is the occlusion test's cost: timed as culling.
        if renderer.depth_pyramid().is_some() {
            t.span(&rec, Phase::Cull, |rec| renderer.record_depth_pyramid(rec));
        }
        let signals = ahead.as_ref().map(Ahead::signals).unwrap_or_default();
        let ended = end(rec, renderer, &mut t, (&waits, &signals));
        // While the frame draws: its steps' timings, then the next frame's
        // steps beside it.
        let stepped = match (ahead.as_mut(), simulation.as_mut(), &ended) {
            (Some(ahead), Some(simulation), Ok(_)) => {
                let timed = if steps > 0 { ahead.collect() } else { Ok(None) };
                timed.and_then(|timed| {
                    if next_steps > 0 {
                        ahead.submit(Some(gpu), simulation, buffer, next_steps)?;
                    }
                    Ok(timed)
                })
            }
            _ => Ok(None),
        };
        // Nothing the frame reads may change or go while it runs: waited
        // for on every path.
        let waited = commands.wait("rendering a frame");
        renderer.end_frame(ended.is_ok() && waited.is_ok() && stepped.is_ok());
        let ended = ended?;
        waited?;
        let stepped = stepped?;
        self.note_tip_jumps();
        let mut stats = self.read_stats()?;
        if let (Some(times), Some((wind, grass))) = (stats.timings.as_mut(), stepped) {
            times.wind += wind;
            times.grass += grass;
        }
        Ok(Some((ended, stats)))
    }

    /// Keeps the largest tip jumps the cover's passes have seen.
    fn note_tip_jumps(&mut self) {
        if let Some((pass, _)) = &self.cover {
            let (far, all) = pass.tip_jumps();
            let (old_far, old_all) = self.cover_tip_jumps;
            self.cover_tip_jumps = (old_far.max(far), old_all.max(all));
        }
    }

    /// Before a frame of `steps` is recorded: its uniforms set, the
    /// colliders placed, the timer sized; what its cull pass tests blades
    /// against.
    fn prepare(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
    ) -> Result<Option<Occluders>> {
        if steps > 0 && self.simulation.is_none() {
            return Err(Error::InvalidInput(
                "a still of blades at rest cannot be simulated".into(),
            ));
        }
        self.renderer.set_uniforms(uniforms);
        self.camera_xz = glam::Vec2::new(uniforms.camera_pos[0], uniforms.camera_pos[2]);
        if let Some(follow) = &mut self.ground_follow {
            // The previous frame was waited for: its mesh is free to go.
            let eye = glam::Vec3::from_slice(&uniforms.camera_pos[..3]);
            let centre = terrain::mesh_centre(&follow.scene, eye);
            if centre != follow.centre {
                if let Some(grid) = terrain::mesh(&follow.scene, eye) {
                    self.renderer.set_terrain(gpu, &self.commands, &grid)?;
                }
                follow.centre = centre;
            }
        }
        let occluders = self
            .renderer
            .begin_frame(glam::Mat4::from_cols_array_2d(&uniforms.view_proj));
        // The colliders are drawn where the blades see them after the steps.
        if let Some(s) = &self.simulation {
            self.renderer.place_colliders(s.time_after(steps) as f32);
        }
        // Two spans per simulation step, eight for the frame's own phases,
        // one for the wind window's move.
        if let Some(timer) = self.timer.as_mut() {
            let pairs = u32::try_from(steps.saturating_mul(2).saturating_add(9)).map_err(|_| {
                Error::InvalidInput(format!(
                    "{steps} simulation steps in one frame are too many to time"
                ))
            })?;
            timer.reserve(gpu, pairs)?;
        }
        Ok(occluders)
    }

    /// What the frame just submitted measured of itself.
    fn read_stats(&self) -> Result<FrameStats> {
        let timings = match &self.timer {
            Some(t) => {
                let mut times = FrameTimings::default();
                for (phase, ms) in t.read()? {
                    *times.get_mut(phase) += ms;
                }
                Some(times)
            }
            None => None,
        };
        let stats = FrameStats {
            statistics: self.statistics.read()?,
            shadow_statistics: if self.renderer.shadows() {
                self.shadow_statistics.read()?
            } else {
                None
            },
            timings,
            cull: self.cull.as_ref().map(CullPass::counts),
        };
        Ok(stats)
    }
}

/// What a frame's graphics submissions wait for and signal: the
/// simulation's steps beside the drawing (`ahead.rs`), else nothing.
type Sync<'a> = (
    &'a [vk::SemaphoreSubmitInfo<'static>],
    &'a [vk::SemaphoreSubmitInfo<'static>],
);

/// Whether `scene`'s frames run their steps beside the drawing
/// (`render.overlap`): "auto" where the device has a second queue, "on"
/// anywhere; never for blades at rest or with a `[grass.cover]`, whose
/// tiles read the wind the next steps would be writing.
fn overlaps(gpu: &Gpu, scene: &Scene, dynamic: bool) -> Result<bool> {
    let mode = scene.render.overlap;
    if !dynamic || mode == Overlap::Off {
        return Ok(false);
    }
    if scene.grass.cover.is_some() {
        return match mode {
            Overlap::On => Err(Error::InvalidInput(
                "render.overlap = \"on\" with [grass.cover]: its tiles read the wind that the next frame's steps write beside the drawing; set render.overlap = \"auto\" or \"off\"".into(),
            )),
            _ => Ok(false),
        };
    }
    // A second queue is only made with timeline semaphores (src/gpu/device.rs).
    Ok(mode == Overlap::On || gpu.has_simulation_queue())
}

/// What a frame measured of itself, read after it ran.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameStats {
    pub statistics: Option<PipelineStatistics>,
    pub shadow_statistics: Option<PipelineStatistics>,
    pub timings: Option<FrameTimings>,
    pub cull: Option<CullCounts>,
}

/// Renders one frame of `blades` at rest as `scene` lights them: the
/// building block of the still-picture tests. Returns the frame and the
/// MSAA count used.
pub fn render_blades(
    gpu: &Gpu,
    scene: &Scene,
    blades: &[Blade],
    (width, height): (u32, u32),
    msaa: u32,
    view: ViewMode,
) -> Result<(Frame, u32)> {
    let mut recorder = FrameRecorder::new(gpu, scene, (width, height), msaa, blades, None)?;
    let uniforms = FrameUniforms::new(scene, width, height, view, 0.0);
    let frame = recorder.render(gpu, &uniforms, 0)?;
    Ok((frame, recorder.samples()))
}

/// Refuses, before anything is allocated, a view whose grass buffers,
/// frame targets (colour and depth per sample, the resolved image and its
/// read-back copy) and shadow map would not fit the GPU memory budget; the
/// wind grid checks its own.
pub fn check_fits(gpu: &Gpu, scene: &Scene, width: u32, height: u32, msaa: u32) -> Result<()> {
    let pixels = width as u64 * height as u64;
    // The cover's blades: their control points, and the cull pass's lists.
    let cover = scene
        .grass
        .cover
        .as_ref()
        .map_or(0, crate::scene::cover::most_blades);
    // The blades the cover's dynamics keep near the camera: the grass
    // step's buffers and the control points it writes.
    let kept = scene.grass.cover.as_ref().map_or(0, |c| {
        if c.simulate_radius() > 0.0 {
            crate::scene::cover::kept_tiles(c, glam::Vec2::ZERO).blade_count()
        } else {
            0
        }
    });
    let what = match &scene.grass.cover {
        Some(c) => format!(
            "{} blades and grass.cover's {cover} (density {} a square metre, view_distance {} m; {kept} of them within simulate_radius {} m keep a state) at {width}x{height} with {msaa}x MSAA",
            scene.blade_count(),
            c.density(),
            c.view_distance,
            c.simulate_radius()
        ),
        None => format!(
            "{} blades at {width}x{height} with {msaa}x MSAA",
            scene.blade_count()
        ),
    };
    let drawn = scene.blade_count().saturating_add(cover as usize);
    gpu.check_fits(
        &what,
        crate::compute::grass_pass::device_bytes(scene.blade_count(), !scene.colliders.is_empty())
            + cover * 4 * std::mem::size_of::<crate::model::BladeVertex>() as u64
            + crate::compute::grass_pass::device_bytes(kept as usize, false)
            + if scene.cull.enabled {
                crate::render::cull::device_bytes(drawn)
            } else {
                0
            }
            + if scene.cull.enabled && scene.cull.occlusion {
                crate::render::depth_pyramid::device_bytes(width, height)
            } else {
                0
            }
            + pixels * (8 * msaa as u64 + 8)
            + 4 * (scene.light.shadow_map as u64).pow(2),
    )
}
