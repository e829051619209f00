//! What the person at the window has set up, apart from the window and the
//! GPU that show it: the fly camera, pause and time scale, the keys held,
//! the pointer, the wind keys and gusts, the ball, the script's actions to
//! come. `ViewState::act` applies one action; what only the window can do
//! (stop, resize, the overlay's panels) it hands back as `ForWindow`.

use std::collections::HashMap;
use std::time::Instant;

use glam::{Vec3, Vec3Swizzles};

use super::ball::Ball;
use super::script::{self, Action};
use super::wind_controls::{self, WindControls};
use crate::error::Result;
use crate::report::legend;
use crate::scene::{Scene, ViewMode};

/// A fly camera: where it is, where it looks (yaw about y, pitch), how fast.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: Vec3,
    yaw: f32,
    pitch: f32,
    speed: f32,
}

impl Camera {
    pub fn looking(eye: Vec3, target: Vec3) -> Self {
        let d = (target - eye).normalize_or(Vec3::NEG_Z);
        Self {
            eye,
            yaw: d.x.atan2(-d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin(),
            speed: 2.0,
        }
    }

    pub fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(sy * cp, sp, -cy * cp)
    }
}

/// The window as an action sees it: its size (pixels) and the simulated
/// time it shows.
#[derive(Clone, Copy, Debug)]
pub struct Seen {
    pub size: (u32, u32),
    pub time: f64,
}

/// What an action leaves to the window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ForWindow {
    Nothing,
    Stop,
    ToggleKeys,
    ToggleOverlay,
    Resize(u32, u32),
}

pub struct ViewState {
    pub scene: Scene,
    pub view: ViewMode,
    camera: Camera,
    /// The scene's camera path is followed until the user flies.
    flying: bool,
    pub paused: bool,
    /// Single steps asked for (`.`) since the last frame.
    pub steps_asked: u64,
    pub time_scale: f64,
    /// The flying keys held: until released (None) or until a scripted
    /// hold ends.
    pub held: HashMap<char, Option<Instant>>,
    /// The pointer's last position in the window (pixels).
    pub pointer: (f64, f64),
    /// The left button is down: where it went down, and whether the
    /// pointer has moved far enough since for a drag rather than a click.
    pub pressed: Option<((f64, f64), bool)>,
    pub wind: WindControls,
    /// The wind keys or a gust changed the wind's drive since the last frame.
    pub wind_changed: bool,
    /// The ball B brings, while it is out.
    pub ball: Option<Ball>,
    /// Why B brings no ball, where it cannot (the scene has
    /// `MAX_COLLIDERS` colliders of its own); None: it can.
    no_ball: Option<String>,
    /// The script's actions to come, at seconds after the first frame.
    script: Vec<(f64, Action)>,
    pub screenshot_asked: bool,
}

impl ViewState {
    /// At the scene's start, seen from its camera at simulated time `start`.
    pub fn new(
        scene: Scene,
        view: ViewMode,
        script: Vec<(f64, Action)>,
        no_ball: Option<String>,
    ) -> Self {
        let (eye, target) = scene.camera.at(scene.render.start);
        Self {
            wind: WindControls::new(&scene),
            camera: Camera::looking(eye, target),
            flying: false,
            view,
            scene,
            paused: false,
            steps_asked: 0,
            time_scale: 1.0,
            held: HashMap::new(),
            pointer: (0.0, 0.0),
            pressed: None,
            wind_changed: false,
            ball: None,
            no_ball,
            script,
            screenshot_asked: false,
        }
    }

    /// The scene as a frame shows it: the fly camera once the user flew.
    pub fn shown_scene(&self) -> Scene {
        let mut scene = self.scene.clone();
        if self.flying {
            scene.camera.position = self.camera.eye.to_array();
            scene.camera.target = (self.camera.eye + self.camera.forward()).to_array();
            scene.camera.path.clear();
        }
        scene
    }

    /// The fly camera takes over where the scene's camera is at `time`.
    pub fn take_over_camera(&mut self, time: f64) {
        if !self.flying {
            let speed = self.camera.speed;
            let (eye, target) = self.scene.camera.at(time as f32);
            self.camera = Camera::looking(eye, target);
            self.camera.speed = speed;
            self.flying = true;
        }
    }

    /// The script's next action if it is due `since_start` seconds after
    /// the first frame: one a frame, as a person's keys come.
    pub fn scripted(&mut self, since_start: f64) -> Option<Action> {
        let due = self.script.first().is_some_and(|(t, _)| *t <= since_start);
        due.then(|| self.script.remove(0).1)
    }

    /// Applies `action` at `now` to the window as `seen`.
    pub fn act(&mut self, action: Action, now: Instant, seen: Seen) -> ForWindow {
        match action {
            Action::Quit | Action::Close => return ForWindow::Stop,
            Action::Pause => self.paused = !self.paused,
            Action::Step => {
                self.paused = true;
                self.steps_asked += 1;
            }
            Action::Slower => self.time_scale = (self.time_scale / 2.0).max(1.0 / 64.0),
            Action::Faster => self.time_scale = (self.time_scale * 2.0).min(8.0),
            Action::ToggleLod => self.scene.lod.enabled = !self.scene.lod.enabled,
            Action::CycleView => {
                self.view = match self.view {
                    ViewMode::Shaded => ViewMode::Lod,
                    ViewMode::Lod => ViewMode::Motion,
                    ViewMode::Motion => ViewMode::Shaded,
                };
                announce_view(self.view, self.scene.lod.levels);
            }
            Action::Screenshot => self.screenshot_asked = true,
            Action::Help => return ForWindow::ToggleKeys,
            Action::ToggleOverlay => return ForWindow::ToggleOverlay,
            Action::WindSpeed(steps) => {
                self.wind.strengthen(steps);
                self.wind_changed = true;
            }
            Action::WindTurn(steps) => {
                self.wind.turn(steps);
                self.wind_changed = true;
            }
            Action::Click(x, y) => self.drop_gust((x, y), seen),
            Action::Ball => self.toggle_ball(seen),
            Action::RollTo(x, y) => self.roll_ball((x, y), seen),
            Action::Hold(key, seconds) => {
                self.take_over_camera(seen.time);
                let until = now + std::time::Duration::from_secs_f64(seconds);
                self.held.insert(key, Some(until));
            }
            Action::Drag(dx, dy) => {
                self.take_over_camera(seen.time);
                self.camera.yaw += dx * 0.2f32.to_radians();
                self.camera.pitch = (self.camera.pitch - dy * 0.2f32.to_radians())
                    .clamp(-89f32.to_radians(), 89f32.to_radians());
            }
            Action::Wheel(notches) => {
                self.camera.speed = (self.camera.speed * 1.25f32.powf(notches)).clamp(0.05, 200.0)
            }
            Action::Resize(w, h) => return ForWindow::Resize(w, h),
        }
        ForWindow::Nothing
    }

    /// The ground point seen at pixel `at` of the window.
    fn ground_at(&self, at: (f32, f32), seen: Seen) -> Option<Vec3> {
        wind_controls::ground_point(&self.shown_scene(), seen.size, at, seen.time as f32)
    }

    /// A gust on the ground under pixel `at`, blowing from now along the
    /// wind's heading.
    fn drop_gust(&mut self, at: (f32, f32), seen: Seen) {
        let time = seen.time as f32;
        match self.ground_at(at, seen) {
            Some(ground) => {
                self.wind.drop_gust(ground, time);
                self.wind_changed = true;
                println!(
                    "gust at ({:.2}, {:.2}) m from t {time:.2} s for {} s, along {:.0} degrees",
                    ground.x,
                    ground.z,
                    wind_controls::GUST_SECONDS,
                    self.wind.heading_deg
                );
            }
            None => println!("no gust: the pointer is above the horizon"),
        }
    }

    /// B: the ball onto the ground where the window's middle looks, or away.
    fn toggle_ball(&mut self, seen: Seen) {
        if self.ball.take().is_some() {
            println!("ball taken away");
            return;
        }
        let middle = (seen.size.0 as f32 / 2.0, seen.size.1 as f32 / 2.0);
        match self.ground_at(middle, seen) {
            Some(ground) => self.bring_ball(ground, seen),
            None => println!("no ball: the middle of the window looks above the horizon"),
        }
    }

    fn bring_ball(&mut self, ground: Vec3, seen: Seen) {
        if let Some(why) = &self.no_ball {
            println!("no ball: {why}");
            return;
        }
        match ball_rectangle(&self.shown_scene(), seen.time as f32) {
            Ok((low, high)) => {
                let ball = Ball::new(ground, low, high, self.scene.ground.terrain());
                println!("ball at ({:.4}, {:.4}) m", ball.centre.x, ball.centre.z);
                self.ball = Some(ball);
            }
            Err(e) => println!("no ball: {e}"),
        }
    }

    /// A right click: the ball rolls to the ground under the pointer.
    fn roll_ball(&mut self, at: (f32, f32), seen: Seen) {
        let Some(ground) = self.ground_at(at, seen) else {
            println!("the ball stays: the pointer is above the horizon");
            return;
        };
        if self.ball.is_none() {
            self.bring_ball(ground, seen);
        }
        if let Some(ball) = self.ball.as_mut() {
            let goal = ball.roll_to(ground);
            println!(
                "ball rolling to ({:.4}, {:.4}) m from t {:.4} s",
                goal.x, goal.z, seen.time
            );
        }
    }

    /// What the overlay says about the ball.
    pub fn ball_readout(&self) -> Option<String> {
        let ball = self.ball.as_ref()?;
        let at = format!("({:.1}, {:.1}) m", ball.centre.x, ball.centre.z);
        Some(match ball.goal {
            Some(goal) => format!(
                "at {at}, {:.1} m/s to ({:.1}, {:.1}); right click: roll it, B: away",
                ball.velocity.length(),
                goal.x,
                goal.z
            ),
            None => format!("at {at}; right click: roll it, B: away"),
        })
    }

    /// What the overlay says about the wind at simulated `time`.
    pub fn wind_readout(&self, time: f64) -> String {
        let drive = match self.wind.inflow_now() {
            Some(inflow) => format!(
                "inflow {:.1} m/s towards {:.0} deg",
                inflow.speed.abs(),
                inflow.heading
            ),
            None => format!("sources x{:.2}", self.wind.strength_scale),
        };
        format!(
            "{drive}, turned {:.0} deg, gusts blowing: {}",
            self.wind.heading_deg,
            self.wind.gusts_blowing(time as f32)
        )
    }

    /// Moves the camera by the keys held for `seconds`.
    pub fn fly(&mut self, seconds: f32, now: Instant) {
        self.held
            .retain(|_, until| until.is_none_or(|until| until > now));
        if self.held.is_empty() {
            return;
        }
        let forward = self.camera.forward();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let mut direction = Vec3::ZERO;
        for key in self.held.keys() {
            direction += match key {
                'w' => forward,
                's' => -forward,
                'd' => right,
                'a' => -right,
                'e' => Vec3::Y,
                'q' => Vec3::NEG_Y,
                _ => Vec3::ZERO,
            };
        }
        self.camera.eye += direction.normalize_or_zero() * self.camera.speed * seconds;
    }
}

/// The rectangle (x, z) of the ground the ball may roll on: the wind's
/// domain, so that it pushes air wherever it goes; with a `[grass.cover]`,
/// whose wind window follows the camera, the window under the camera
/// `scene` has at `time` (to within the cell it moves by).
pub fn ball_rectangle(scene: &Scene, time: f32) -> Result<(glam::Vec2, glam::Vec2)> {
    let grid = scene.wind_grid()?;
    let size = (grid.cells.as_vec3() * grid.cell).xz();
    let low = if scene.grass.cover.is_some() {
        let (eye, _) = scene.camera.at(time);
        eye.xz() - 0.5 * size
    } else {
        grid.origin.xz()
    };
    Ok((low, low + size))
}

/// The keys' help, printed when H shows it in the overlay.
pub fn print_help() {
    println!("{}", script::help());
}

/// Says on the terminal which view the window shows and, for a debug
/// view, what its colours mean: the key is in the overlay too, but the
/// overlay can be hidden or too small to hold it.
pub fn announce_view(view: ViewMode, levels: [u32; 3]) {
    let name = format!("{view:?}").to_lowercase();
    match legend::words(view, levels) {
        Some(words) => println!("view {name}: {words}"),
        None => println!("view {name}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cover's wind window follows the camera, and the ball's rectangle
    /// with it: 500 m along steppe's flight it lies around the camera
    /// there, not where the flight began; a bounded meadow's is its wind
    /// domain whenever it is asked.
    #[test]
    fn the_balls_rectangle_is_the_wind_window_under_the_camera_now() {
        let steppe = Scene::builtin("steppe").unwrap();
        for time in [0.0, 50.0] {
            let (low, high) = ball_rectangle(&steppe, time).unwrap();
            let (eye, _) = steppe.camera.at(time);
            let middle = (low + high) * 0.5;
            assert!(middle.distance(eye.xz()) < 1e-3, "{middle} vs {eye}");
            let size = high - low;
            assert!(
                (size.x - steppe.wind.window[0]).abs() < 1e-3
                    && (size.y - steppe.wind.window[1]).abs() < 1e-3,
                "{size}"
            );
        }
        let roll = Scene::builtin("roll").unwrap();
        let grid = roll.wind_grid().unwrap();
        for time in [0.0, 50.0] {
            assert_eq!(ball_rectangle(&roll, time).unwrap().0, grid.origin.xz());
        }
    }
}
