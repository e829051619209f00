//! `meadow view`: the meadow live in a window. Every frame runs both of
//! the paper's phases, as `render` does, and shows the frame through a
//! FIFO swapchain instead of reading it back. Simulated time follows the
//! clock in the scene's fixed steps; when a frame takes longer than the
//! steps it may catch up (`MAX_CATCH_UP_S` of simulated time), time slows
//! down instead of the steps piling up.

pub mod ball;
pub mod overlay;
pub mod script;
pub mod state;
pub mod wind_controls;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::Vec3;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::commands::on_gpu;
use crate::compute::StepPace;
use crate::error::{Error, Result};
use crate::frame::timing::Phase;
use crate::frame::{FrameRecorder, FrameStats};
use crate::gpu::swapchain::Presented;
use crate::gpu::{
    surface, DependsOn, DeviceMemory, Gpu, GpuOptions, Surface, Swapchain, ValidationReport,
};
use crate::model::contact::{Collider, MAX_COLLIDERS};
use crate::render::FrameUniforms;
use crate::report::{files, legend};
use crate::scene::{field, Scene, ViewMode};
use ball::{Arrived, Ball};
use overlay::{Overlay, Readout};
use script::{Action, Script, FLYING_KEYS};
use state::{ball_rectangle, ForWindow, Seen, ViewState};

/// Simulated seconds one frame may catch up at most: beyond it, time in
/// the window runs slower than the clock.
pub const MAX_CATCH_UP_S: f64 = 0.1;

/// GPU time a frame's simulation steps may take, where a step is slow (a
/// CPU device): fewer steps a frame keep the window answering, and the
/// simulated time per second of the clock is the same either way.
pub const STEP_BUDGET_MS: f64 = 33.0;

/// How far (pixels) the pointer may move between press and release for a
/// click (a gust) rather than a drag (a look).
const CLICK_SLOP_PX: f64 = 3.0;

#[derive(Clone, Debug)]
pub struct ViewRequest {
    pub scene: Scene,
    /// The window's inner size at the start.
    pub width: u32,
    pub height: u32,
    pub msaa: u32,
    pub view: ViewMode,
    pub script: Option<Script>,
    /// Where P writes its screenshots.
    pub screenshots: PathBuf,
    pub gpu: GpuOptions,
    /// Set non-zero (to a signal's number) to close the window between
    /// frames: the viewer stops as after Esc, and says so.
    pub stop: Option<Arc<AtomicUsize>>,
}

/// What a session in the window did.
#[derive(Clone, Debug, Default)]
pub struct ViewReport {
    /// The signal that stopped the viewer (`ViewRequest::stop`), if one did.
    pub stopped_by: Option<usize>,
    pub frames: u64,
    pub simulated_seconds: f64,
    /// From the first frame shown to the last.
    pub wall_seconds: f64,
    /// Before the first frame and after the last: the GPU's start-up,
    /// the field, the pipelines, the scene's own start, the teardown.
    pub start_seconds: f64,
    pub screenshots: Vec<PathBuf>,
    /// The device memory the session's allocations held before the
    /// window's objects went, and at most (the swapchain's images, the
    /// driver's, not counted).
    pub device_memory: DeviceMemory,
    pub validation: ValidationReport,
}

impl ViewReport {
    /// Frames a second after the first (which opens the clock).
    pub fn fps(&self) -> f64 {
        self.frames.saturating_sub(1) as f64 / self.wall_seconds.max(1e-9)
    }
}

/// Opens the window and runs until Esc, the window's close or the script's
/// end of input. Refused with one line where there is no display.
pub fn view(request: &ViewRequest) -> Result<ViewReport> {
    request.scene.validate()?;
    request.scene.wind_grid()?;
    let display_set = ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()));
    if !display_set {
        return Err(no_display("neither DISPLAY nor WAYLAND_DISPLAY is set"));
    }
    let event_loop = EventLoop::new().map_err(|e| no_display(&e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let display = event_loop
        .display_handle()
        .map_err(|e| no_display(&e.to_string()))?
        .as_raw();
    let mut options = request.gpu.clone();
    options.window_extensions = surface::window_extensions(display)?;
    let started = Instant::now();
    let (mut report, validation) = on_gpu(&options, |gpu| {
        let mut app = App {
            gpu,
            request,
            live: None,
            error: None,
            report: ViewReport::default(),
        };
        let ran = event_loop.run_app(&mut app);
        // The window's GPU objects go before the GPU is torn down.
        let simulated = app.live.as_ref().map_or(0.0, Live::time);
        app.report.device_memory = gpu.device_memory();
        let shown = app.live.as_ref().and_then(|l| {
            l.first_frame
                .map(|first| l.last_frame.duration_since(first).as_secs_f64())
        });
        drop(app.live.take());
        if let Some(e) = app.error.take() {
            return Err(e);
        }
        ran.map_err(|e| Error::InvalidInput(format!("the window's event loop failed: {e}")))?;
        app.report.simulated_seconds = simulated;
        app.report.wall_seconds = shown.unwrap_or(0.0);
        Ok(app.report)
    })?;
    report.start_seconds = started.elapsed().as_secs_f64() - report.wall_seconds;
    report.validation = validation;
    report.validation.check()?;
    Ok(report)
}

fn no_display(why: &str) -> Error {
    Error::InvalidInput(format!(
        "meadow view needs a display ({why}); on a machine without one run it under Xvfb \
         (xvfb-run -a meadow view), or write frames with `meadow render` (--video for a video)"
    ))
}

struct App<'a> {
    gpu: &'a Gpu,
    request: &'a ViewRequest,
    live: Option<Live>,
    /// The first failure: the loop stops at it and `view` returns it.
    error: Option<Error>,
    report: ViewReport,
}

/// The window and what draws into it. The surface dies before the window
/// by its type (`DependsOn`); the swapchain, which holds the surface too,
/// is let go in `Drop`, before either. The overlay and the recorder use
/// the device alone.
struct Live {
    overlay: Overlay,
    recorder: FrameRecorder,
    swapchain: Option<Swapchain>,
    /// The surface, and the window it shows in.
    surface: DependsOn<Arc<Surface>, Window>,
    /// What the person at the window set up (src/commands/view/state.rs).
    state: ViewState,
    /// The last frame's measurements, for the overlay.
    last_stats: FrameStats,
    first_frame: Option<Instant>,
    last_frame: Instant,
    /// Seconds between frames on the clock, smoothed over about ten.
    frame_seconds: f64,
    stale: bool,
    screenshots_dir: PathBuf,
    /// GPU time of one simulation step, last measured (None: not yet, or
    /// no timestamps).
    step_ms: Option<f64>,
}

impl Drop for Live {
    fn drop(&mut self) {
        // The swapchain holds the surface alive: it goes before the window.
        self.swapchain = None;
    }
}

impl Live {
    fn new(gpu: &Gpu, request: &ViewRequest, event_loop: &ActiveEventLoop) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title(format!("meadow - {}", request.scene.name))
            .with_inner_size(PhysicalSize::new(request.width, request.height));
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| Error::InvalidInput(format!("the window could not be made: {e}")))?;
        let handles = (window.display_handle(), window.window_handle());
        let (Ok(display), Ok(handle)) = handles else {
            return Err(Error::InvalidInput(
                "the window has no handle Vulkan can draw into".into(),
            ));
        };
        let surface = Arc::new(Surface::new(gpu, display.as_raw(), handle.as_raw())?);
        let scene = request.scene.clone();
        let size = window.inner_size();
        let (width, height) = (size.width.max(1), size.height.max(1));
        // Made with a ball among the colliders, so that each blade keeps a
        // pressed state for it; it is taken away before the first frame
        // and B brings it back.
        let no_ball = if scene.colliders.len() >= MAX_COLLIDERS {
            Some(format!(
                "the scene has {MAX_COLLIDERS} colliders, as many as a step simulates"
            ))
        } else {
            None
        };
        let mut made = scene.clone();
        // A window's frame is drawn and shown in one submission, its steps
        // with it: the simulation beside the drawing is the offscreen
        // frame loops' (src/frame/ahead.rs).
        made.render.overlap = crate::scene::Overlap::Off;
        if no_ball.is_none() {
            let (low, high) = ball_rectangle(&scene, 0.0)?;
            let middle = (low + high) * 0.5;
            let mut parked = Ball::new(
                Vec3::new(middle.x, 0.0, middle.y),
                low,
                high,
                scene.ground.terrain(),
            );
            made.colliders.push(parked.stretch(0.0, 0.0).0);
        }
        crate::frame::check_fits(gpu, &made, width, height, request.msaa)?;
        let blades = scene.field()?;
        let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
        let mut recorder = FrameRecorder::new(
            gpu,
            &made,
            (width, height),
            request.msaa,
            &blades,
            Some(&dynamic),
        )?;
        recorder.set_colliders(gpu, &scene.colliders)?;
        // The scene's own start: the window opens on what `render` shows first.
        let mut steps = recorder.steps_until(scene.render.start as f64)?;
        let mut pace = StepPace::default();
        while steps > 0 {
            steps -= pace.run(steps, |batch| recorder.simulate(batch))?;
        }
        let script = request.script.clone().unwrap_or_default().actions;
        if request.view != ViewMode::Shaded {
            state::announce_view(request.view, scene.lod.levels);
        }
        Ok(Self {
            state: ViewState::new(scene, request.view, script, no_ball),
            overlay: Overlay::default(),
            recorder,
            swapchain: None,
            surface: DependsOn::new(surface, window),
            last_stats: FrameStats::default(),
            first_frame: None,
            last_frame: Instant::now(),
            frame_seconds: 0.0,
            stale: true,
            screenshots_dir: request.screenshots.clone(),
            step_ms: None,
        })
    }

    /// Simulated time so far.
    fn time(&self) -> f64 {
        self.recorder.simulation().map_or(0.0, |s| s.time_after(0))
    }

    fn dt(&self) -> f64 {
        self.recorder
            .simulation()
            .map_or(1.0 / 60.0, |s| s.dt() as f64)
    }

    /// The window as an action sees it now.
    fn seen(&self) -> Seen {
        let size = self.surface.keeper().inner_size();
        Seen {
            size: (size.width, size.height),
            time: self.time(),
        }
    }

    /// Applies `action` (a key, the pointer, the script); returns false
    /// when the viewer should stop.
    fn act(&mut self, action: Action, now: Instant) -> bool {
        match self.state.act(action, now, self.seen()) {
            ForWindow::Nothing => {}
            ForWindow::Stop => return false,
            ForWindow::ToggleKeys => {
                self.overlay.keys_shown = !self.overlay.keys_shown;
                if self.overlay.keys_shown {
                    state::print_help();
                }
            }
            ForWindow::ToggleOverlay => self.overlay.shown = !self.overlay.shown,
            ForWindow::Resize(w, h) => {
                let _ = self
                    .surface
                    .keeper()
                    .request_inner_size(PhysicalSize::new(w, h));
            }
        }
        true
    }

    /// One frame: the script's due action, the camera, the simulation's
    /// steps, and the frame shown. Returns false when the viewer should stop.
    fn frame(&mut self, gpu: &Gpu, report: &mut ViewReport) -> Result<bool> {
        let now = Instant::now();
        let (go_on, wall) = self.tick(now);

        // Minimised or out of date: nothing to show, and time waits.
        let Some(index) = self.acquire(gpu)? else {
            return Ok(go_on);
        };
        if std::mem::take(&mut self.state.wind_changed) {
            let (inflow, sources) = self.state.wind.drive();
            self.recorder.set_wind_drive(gpu, inflow, &sources)?;
        }
        let steps = self.steps_for(wall)?;
        update_colliders(
            gpu,
            &mut self.recorder,
            &self.state.scene.colliders,
            self.state.ball.as_mut(),
            steps,
        )?;
        let time = self.time() + steps as f64 * self.dt();
        let scene = self.state.shown_scene();
        let swapchain = self.swapchain.as_ref().expect("acquired from it");
        let extent = swapchain.extent;
        let uniforms = FrameUniforms::new(
            &scene,
            extent.width,
            extent.height,
            self.state.view,
            time as f32,
        );
        let state = &self.state;
        let readout = Readout {
            scene: &state.scene.name,
            fps: self.fps(),
            stats: &self.last_stats,
            blades: self.recorder.blades().count() as usize,
            time,
            time_scale: state.time_scale,
            paused: state.paused,
            lod: state.scene.lod.enabled,
            view: state.view,
            lod_levels: state.scene.lod.levels,
            wind: state.wind_readout(self.time()),
            ball: state.ball_readout(),
        };
        let scale = self.surface.keeper().scale_factor() as f32;
        let prepared = self
            .overlay
            .prepare(gpu, swapchain.format, extent, scale, &readout)?;
        let (presented, stats) = self.recorder.present(
            gpu,
            &uniforms,
            steps,
            swapchain,
            index,
            self.overlay.to_draw(&prepared),
        )?;
        self.overlay.finish(prepared)?;
        self.stale |= presented == Presented::Stale;
        if let Some(t) = stats.timings.filter(|_| steps > 0) {
            self.step_ms = Some((t.get(Phase::Wind) + t.get(Phase::Grass)) / steps as f64);
        }
        self.first_frame.get_or_insert(now);
        report.frames += 1;
        if std::mem::take(&mut self.state.screenshot_asked) {
            let shot = (&uniforms, time, &scene, (extent.width, extent.height));
            report
                .screenshots
                .push(self.take_screenshot(gpu, shot, report.screenshots.len())?);
        }
        self.show_title(&stats);
        self.last_stats = stats;
        Ok(go_on)
    }

    /// The frame's one scripted action (false: it quits, after this frame)
    /// and the seconds since the last frame that time and flying follow.
    fn tick(&mut self, now: Instant) -> (bool, f64) {
        let since_start = self
            .first_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        // One scripted action a frame, as a person's keys come: on a slow
        // device actions due together are not all applied before one
        // frame (a screenshot then shows what came before the next key).
        let go_on = match self.state.scripted(since_start) {
            Some(action) => self.act(action, now),
            None => true,
        };
        let elapsed = now.duration_since(self.last_frame).as_secs_f64();
        self.update_fps(elapsed);
        // Time and flying follow the clock, but not across a long stall
        // (a window being dragged, a slow first frame).
        let wall = elapsed.min(0.25);
        self.last_frame = now;
        self.state.fly(wall as f32, now);
        (go_on, wall)
    }

    /// A screenshot of the frame (its uniforms, time, scene and size),
    /// the `n`-th, said on the terminal.
    fn take_screenshot(
        &mut self,
        gpu: &Gpu,
        (uniforms, time, scene, size): (&FrameUniforms, f64, &Scene, (u32, u32)),
        n: usize,
    ) -> Result<PathBuf> {
        let path = self.screenshot(gpu, uniforms, n)?;
        self.say_screenshot(&path, time, scene, size);
        Ok(path)
    }

    /// The swapchain made again where it is out of date, the recorder's
    /// targets fitted to it, and an image acquired (None: minimised, or
    /// out of date again).
    fn acquire(&mut self, gpu: &Gpu) -> Result<Option<u32>> {
        if self.stale {
            let size = self.surface.keeper().inner_size();
            let wanted = vk::Extent2D {
                width: size.width,
                height: size.height,
            };
            let old = self.swapchain.take();
            self.swapchain = Swapchain::new(gpu, &self.surface, wanted, old)?;
            self.stale = false;
        }
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(None);
        };
        let extent = (swapchain.extent.width, swapchain.extent.height);
        self.recorder.resize(gpu, &self.state.scene, extent)?;
        let index = swapchain.acquire()?;
        self.stale |= index.is_none();
        Ok(index)
    }

    /// The simulation steps this frame runs: those asked for one by one,
    /// and (unpaused) those that bring simulated time `wall` seconds of the
    /// clock further at the time scale, no more than a frame may catch up
    /// or the step budget affords.
    fn steps_for(&mut self, wall: f64) -> Result<u64> {
        let mut steps = std::mem::take(&mut self.state.steps_asked);
        if !self.state.paused && self.first_frame.is_some() {
            let target = self.time() + wall * self.state.time_scale;
            let catch_up = (MAX_CATCH_UP_S / self.dt()).ceil() as u64;
            let affordable = match self.step_ms {
                Some(ms) if ms > 0.0 => ((STEP_BUDGET_MS / ms) as u64).max(1),
                _ => catch_up,
            };
            steps += self
                .recorder
                .steps_until(target)?
                .min(catch_up)
                .min(affordable);
        }
        Ok(steps)
    }

    /// The frame `render` would write for the same time and camera, as
    /// `view_NNNN.png`: the first number from `n` on that no file in the
    /// folder has yet (a screenshot never replaces a file, an earlier
    /// session's included: the numbering goes on).
    fn screenshot(&mut self, gpu: &Gpu, uniforms: &FrameUniforms, n: usize) -> Result<PathBuf> {
        let dir = &self.screenshots_dir;
        files::ensure_dir(dir)?;
        let mut frame = self.recorder.render(gpu, uniforms, 0)?;
        legend::stamp(&mut frame, self.state.view, self.state.scene.lod.levels);
        let path = (n..)
            .map(|k| dir.join(format!("view_{k:04}.png")))
            .find(|path| !path.exists())
            .expect("a free number below usize::MAX");
        files::write_png(&path, &frame)?;
        Ok(path)
    }

    /// Where a screenshot went and what it shows (and, in a frame too
    /// small for it, the debug view's key in words).
    fn say_screenshot(&self, path: &Path, time: f64, scene: &Scene, (width, height): (u32, u32)) {
        let ball = self
            .state
            .ball
            .as_ref()
            .map(|b| format!(", ball at ({:.4}, {:.4}) m", b.centre.x, b.centre.z))
            .unwrap_or_default();
        println!(
            "wrote {} (simulated time {:.4} s, camera at {:?} looking at {:?}{ball})",
            path.display(),
            time,
            scene.camera.position,
            scene.camera.target
        );
        if let Some(said) = legend::left_out(self.state.view, scene.lod.levels, width, height) {
            println!("{said}");
        }
    }

    /// Frames a second, smoothed over about ten frames.
    fn update_fps(&mut self, elapsed: f64) {
        if elapsed > 0.0 && self.first_frame.is_some() {
            self.frame_seconds = if self.frame_seconds == 0.0 {
                elapsed
            } else {
                0.9 * self.frame_seconds + 0.1 * elapsed
            };
        }
    }

    fn fps(&self) -> f64 {
        if self.frame_seconds > 0.0 {
            1.0 / self.frame_seconds
        } else {
            0.0
        }
    }

    /// FPS, GPU time, blades drawn and time in the title bar too (where
    /// the overlay is hidden, or a window manager lists windows).
    fn show_title(&mut self, stats: &FrameStats) {
        let gpu_ms = stats
            .timings
            .map(|t| format!(", GPU {:.1} ms", t.get(Phase::Frame)))
            .unwrap_or_default();
        let drawn = stats
            .cull
            .map(|c| format!(", {} blades drawn", c.in_view))
            .unwrap_or_default();
        let state = if self.state.paused { ", paused" } else { "" };
        self.surface.keeper().set_title(&format!(
            "meadow - {} - {:.1} FPS{gpu_ms}{drawn} - t {:.2} s x{}{state} (H: keys)",
            self.state.scene.name,
            self.fps(),
            self.time(),
            self.state.time_scale
        ));
    }
}

impl Live {
    /// A key pressed or released: the flying keys are held while down,
    /// the others act once when pressed.
    fn key(&mut self, event: &KeyEvent) -> Option<Action> {
        let name = match &event.logical_key {
            Key::Named(NamedKey::Escape) => Some("esc".to_string()),
            Key::Named(NamedKey::Space) => Some("space".to_string()),
            Key::Named(NamedKey::ArrowUp) => Some("up".to_string()),
            Key::Named(NamedKey::ArrowDown) => Some("down".to_string()),
            Key::Named(NamedKey::ArrowLeft) => Some("left".to_string()),
            Key::Named(NamedKey::ArrowRight) => Some("right".to_string()),
            Key::Character(c) => Some(c.to_lowercase()),
            _ => None,
        };
        let flying = name.as_deref().and_then(|n| {
            n.chars()
                .next()
                .filter(|c| n.len() == 1 && FLYING_KEYS.contains(c))
        });
        match (flying, event.state) {
            (Some(key), ElementState::Pressed) => {
                self.state.take_over_camera(self.time());
                self.state.held.insert(key, None);
                None
            }
            (Some(key), ElementState::Released) => {
                self.state.held.remove(&key);
                None
            }
            (None, ElementState::Pressed) if !event.repeat => {
                name.as_deref().and_then(Action::of_key)
            }
            _ => None,
        }
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.live.is_some() || self.error.is_some() {
            return;
        }
        match Live::new(self.gpu, self.request, event_loop) {
            Ok(live) => self.live = Some(live),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(live) = self.live.as_mut() else {
            return;
        };
        let now = Instant::now();
        let action = match event {
            WindowEvent::CloseRequested => Some(Action::Close),
            WindowEvent::Resized(_) => {
                live.stale = true;
                None
            }
            WindowEvent::RedrawRequested => {
                match live.frame(self.gpu, &mut self.report) {
                    Ok(true) => {}
                    Ok(false) => event_loop.exit(),
                    Err(e) => {
                        self.error.get_or_insert(e);
                        event_loop.exit();
                    }
                }
                None
            }
            WindowEvent::KeyboardInput { event, .. } => live.key(&event),
            WindowEvent::MouseInput {
                state: ElementState::Released,
                button: MouseButton::Right,
                ..
            } => {
                let (x, y) = live.state.pointer;
                Some(Action::RollTo(x as f32, y as f32))
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => match (state, live.state.pressed.take()) {
                (ElementState::Pressed, _) => {
                    live.state.pressed = Some((live.state.pointer, false));
                    None
                }
                // Released where it went down: a click, not a drag.
                (ElementState::Released, Some((_, false))) => {
                    let (x, y) = live.state.pointer;
                    Some(Action::Click(x as f32, y as f32))
                }
                (ElementState::Released, _) => None,
            },
            WindowEvent::CursorMoved { position, .. } => {
                let (x, y) = std::mem::replace(&mut live.state.pointer, (position.x, position.y));
                match live.state.pressed.as_mut() {
                    Some((from, dragged)) => {
                        let moved = (position.x - from.0).hypot(position.y - from.1);
                        *dragged |= moved > CLICK_SLOP_PX;
                        Some(Action::Drag(
                            (position.x - x) as f32,
                            (position.y - y) as f32,
                        ))
                    }
                    None => None,
                }
            }
            WindowEvent::MouseWheel { delta, .. } => Some(Action::Wheel(match delta {
                MouseScrollDelta::LineDelta(_, y) => y,
                MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
            })),
            _ => None,
        };
        if action.is_some_and(|a| !live.act(a, now)) {
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let signal = self
            .request
            .stop
            .as_ref()
            .map_or(0, |s| s.load(Ordering::SeqCst));
        if signal != 0 {
            self.report.stopped_by = Some(signal);
            event_loop.exit();
        } else if let Some(live) = &self.live {
            live.surface.keeper().request_redraw();
        }
    }
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }
}

/// The colliders for a frame's `steps`: the scene's, and the ball's
/// stretch up to the frame's time; uploaded where they changed.
fn update_colliders(
    gpu: &Gpu,
    recorder: &mut FrameRecorder,
    scene_colliders: &[Collider],
    ball: Option<&mut Ball>,
    steps: u64,
) -> Result<()> {
    let mut colliders = scene_colliders.to_vec();
    if let (Some(ball), Some(simulation)) = (ball, recorder.simulation()) {
        let (from, to) = (simulation.time_after(0), simulation.time_after(steps));
        let (stretch, arrived) = ball.stretch(from as f32, to as f32);
        if let Some(Arrived(at)) = arrived {
            println!(
                "ball stopped at ({:.3}, {:.3}) m at t {to:.2} s",
                at.x, at.z
            );
        }
        colliders.push(stretch);
    }
    if colliders != recorder.colliders() {
        recorder.set_colliders(gpu, &colliders)?;
    }
    Ok(())
}

/// Reads and parses `--script FILE`.
pub fn read_script(path: &Path) -> Result<Script> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: format!("--script {}", path.display()),
        source: e,
    })?;
    Script::parse(&path.display().to_string(), &text)
}
