//! The simulating phase alone (src/compute/), wind then grass each step
//! as a frame records it, for tests that read its state, and the
//! invariants that state must keep at any step.

use glam::Vec3;
use meadow::compute::Simulation;
use meadow::frame::BladeBuffer;
use meadow::gpu::{CommandPool, DependsOn, Gpu};
use meadow::model::{BladeVertex, GrassBlade, GrassState};
use meadow::scene::{field, Scene};

use super::to_vec3;

/// How far below the ground plane (y = 0) any control point may go, in
/// metres. The curve lies in its control points' convex hull, so this
/// bounds the drawn blade too.
pub const GROUND_TOLERANCE: f32 = 0.01;

/// What the checks of a run saw, over all of them.
#[derive(Debug)]
pub struct Figures {
    pub steps: u64,
    pub blades: usize,
    pub checks: u32,
    /// The fastest wind anywhere in the grid at any check (m/s).
    pub max_wind: f32,
    /// The lowest control point at any check (m; negative is below ground).
    pub lowest_point: f32,
    /// The largest relative edge-length change at any check.
    pub worst_edge: f32,
    /// The farthest any tip got from its rest place (m).
    pub farthest_tip: f32,
    /// The largest angle of any motion at any check (rad).
    pub largest_angle: f32,
}

/// Steps per command buffer: long enough to keep submissions few, short
/// enough to stay far inside the submission timeout on lavapipe.
pub const STEPS_PER_SUBMIT: u64 = 250;

pub struct SimRig {
    pub blades: Vec<GrassBlade>,
    /// The simulation, which writes the blades' vertices (dropped first).
    simulation: DependsOn<Simulation, BladeBuffer>,
    commands: CommandPool,
}

impl SimRig {
    /// The scene's grass at rest and its wind, still.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Self {
        let rest = scene.field().unwrap();
        let blades = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed).unwrap();
        let commands = CommandPool::new(gpu, "test simulation commands").unwrap();
        let vertices =
            BladeBuffer::uninitialised(gpu, "test blade vertices", blades.len()).unwrap();
        let simulation =
            Simulation::new(gpu, &commands, scene, &blades, vertices.buffer()).unwrap();
        Self {
            blades,
            simulation: DependsOn::new(simulation, vertices),
            commands,
        }
    }

    /// Runs `steps` wind + grass steps, at most STEPS_PER_SUBMIT a submission.
    pub fn run(&mut self, steps: u64) {
        let end = self.steps_done() + steps;
        while self.steps_done() < end {
            let batch = STEPS_PER_SUBMIT.min(end - self.steps_done());
            let rec = self.commands.begin().unwrap();
            self.simulation.record_steps(&rec, batch);
            rec.submit_and_wait("test simulation steps").unwrap();
        }
    }

    /// Keeps a wind window that follows the camera under `eye_xz`
    /// (`Simulation::record_follow`), in a submission of its own; whether
    /// the window moved.
    pub fn follow(&mut self, eye_xz: glam::Vec2) -> bool {
        let before = self.simulation.wind().grid;
        let rec = self.commands.begin().unwrap();
        self.simulation.record_follow(&rec, eye_xz).unwrap();
        rec.submit_and_wait("moving the wind window").unwrap();
        self.simulation.wind().grid != before
    }

    pub fn steps_done(&self) -> u64 {
        self.simulation.steps_done()
    }

    /// Each blade's angles and angular velocities.
    pub fn states(&self, gpu: &Gpu) -> Vec<GrassState> {
        self.simulation
            .grass()
            .expect("a scene with patch blades")
            .read_states(gpu, &self.commands)
            .unwrap()
    }

    /// Blade-steps at an angle cap so far.
    pub fn cap_counts(&self, gpu: &Gpu) -> meadow::model::grass::CapCounts {
        self.simulation.cap_counts(gpu, &self.commands).unwrap()
    }

    /// The 4 control points (and width vectors) of each blade, as drawn.
    pub fn vertices(&self, gpu: &Gpu) -> Vec<BladeVertex> {
        self.simulation
            .keeper()
            .buffer()
            .read_back(gpu, &self.commands, self.blades.len() * 4)
            .unwrap()
    }

    /// The frontal area per wind cell the grass laid last step, in counts
    /// of the canopy unit (two-way coupling; zero otherwise).
    pub fn canopy(&self, gpu: &Gpu) -> Vec<u32> {
        self.simulation
            .wind()
            .read_canopy(gpu, &self.commands)
            .unwrap()
    }

    /// The wind velocity's x, y and z face components.
    pub fn velocity(&self, gpu: &Gpu) -> [Vec<f32>; 3] {
        self.simulation
            .wind()
            .read_velocity(gpu, &self.commands)
            .unwrap()
    }

    /// Reads the wind and the blades back and checks them
    /// (`Figures::check`).
    pub fn check(&self, gpu: &Gpu, figures: &mut Figures) {
        let done = self.steps_done();
        figures.check(
            done,
            &self.blades,
            &self.velocity(gpu),
            &self.states(gpu),
            &self.vertices(gpu),
        );
    }
}

impl Figures {
    /// Checks what must hold at any step of a run, `done` steps in: no NaN
    /// or infinite value in the wind or the blades' state, roots where they
    /// grew, no control point more than GROUND_TOLERANCE under the ground;
    /// panics naming the step and blade. The rest (fastest wind,
    /// edge-length change, tip travel, angles) goes into the figures, for
    /// the caller's bounds.
    pub fn check(
        &mut self,
        done: u64,
        blades: &[GrassBlade],
        velocity: &[Vec<f32>; 3],
        states: &[GrassState],
        out: &[BladeVertex],
    ) {
        self.steps = done;
        self.blades = blades.len();
        self.checks += 1;
        for (axis, v) in velocity.iter().enumerate() {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                panic!("step {done}: wind component {axis} at face {i} is {}", v[i]);
            }
            let fastest = v.iter().fold(0.0f32, |m, x| m.max(x.abs()));
            self.max_wind = self.max_wind.max(fastest);
        }
        for (i, blade) in blades.iter().enumerate() {
            let s = &states[i];
            assert!(
                s.angle.iter().chain(&s.velocity).all(|x| x.is_finite()),
                "step {done}: blade {i} state {s:?}"
            );
            self.largest_angle = s
                .angle
                .iter()
                .fold(self.largest_angle, |m, a| m.max(a.abs()));
            let v = &out[4 * i..4 * i + 4];
            assert!(
                v.iter().all(|v| v
                    .position
                    .iter()
                    .chain(&v.half_width)
                    .all(|x| x.is_finite())),
                "step {done}: blade {i} vertices {v:?}"
            );
            let p: Vec<Vec3> = v.iter().map(|v| to_vec3(v.position)).collect();
            assert_eq!(
                p[0],
                blade.rest_point(0),
                "step {done}: blade {i} root moved"
            );
            for e in 0..3 {
                let rest = blade.rest_point(e + 1).distance(blade.rest_point(e));
                let error = (p[e + 1].distance(p[e]) - rest).abs() / rest;
                self.worst_edge = self.worst_edge.max(error);
            }
            let lowest = p.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
            self.lowest_point = self.lowest_point.min(lowest);
            assert!(
                lowest >= -GROUND_TOLERANCE,
                "step {done}: blade {i} reaches {lowest} m below the ground (tolerance {GROUND_TOLERANCE} m): {p:?}"
            );
            self.farthest_tip = self.farthest_tip.max(p[3].distance(blade.rest_point(3)));
        }
    }
}

impl Default for Figures {
    fn default() -> Self {
        Self {
            steps: 0,
            blades: 0,
            checks: 0,
            max_wind: 0.0,
            lowest_point: f32::INFINITY,
            worst_edge: 0.0,
            farthest_tip: 0.0,
            largest_angle: 0.0,
        }
    }
}
