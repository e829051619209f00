//! The simulating phase alone, wind then grass each step as the renderer
//! records it (src/render/simulation.rs), for tests that read its state.

use meadow::gpu::commands::Commands;
use meadow::gpu::{Buffer, Gpu};
use meadow::render::grass_pass::{vertex_buffer, GrassPass};
use meadow::render::wind_pass::WindPass;
use meadow::scene::{field, Scene};
use meadow::sim::{BladeVertex, GrassBlade, GrassState};

/// Steps per command buffer: long enough to keep submissions few, short
/// enough to stay far inside the submission timeout on lavapipe.
pub const STEPS_PER_SUBMIT: u64 = 250;

pub struct SimRig {
    pub blades: Vec<GrassBlade>,
    commands: Commands,
    wind: WindPass,
    grass: GrassPass,
    vertices: Buffer,
    dt: f32,
    steps_done: u64,
}

impl SimRig {
    /// The scene's grass at rest and its wind, still.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Self {
        let rest = field::generate(&scene.grass, scene.seed).unwrap();
        let blades = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed).unwrap();
        let grid = scene.wind_grid().unwrap();
        let dt = scene.wind.dt;
        let commands = Commands::new(gpu, "test simulation commands").unwrap();
        let wind = WindPass::new(gpu, &commands, grid, &scene.wind.settings()).unwrap();
        let vertices = vertex_buffer(gpu, "test blade vertices", blades.len()).unwrap();
        let grass = GrassPass::new(
            gpu,
            &commands,
            &blades,
            &vertices,
            wind.velocity(),
            &grid,
            dt,
        )
        .unwrap();
        Self {
            blades,
            commands,
            wind,
            grass,
            vertices,
            dt,
            steps_done: 0,
        }
    }

    /// Runs `steps` wind + grass steps, at most STEPS_PER_SUBMIT a submission.
    pub fn run(&mut self, gpu: &Gpu, steps: u64) {
        let end = self.steps_done + steps;
        while self.steps_done < end {
            let batch = STEPS_PER_SUBMIT.min(end - self.steps_done);
            let cmd = self.commands.begin(gpu).unwrap();
            for s in self.steps_done..self.steps_done + batch {
                // Simulated time as the renderer computes it.
                let t = (s as f64 * self.dt as f64) as f32;
                self.wind.record_step(gpu, cmd, t, self.dt);
                self.grass.record_step(gpu, cmd, 0);
            }
            self.commands
                .submit_and_wait(gpu, "test simulation steps")
                .unwrap();
            self.steps_done += batch;
        }
    }

    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    /// Each blade's angles and angular velocities.
    pub fn states(&self, gpu: &Gpu) -> Vec<GrassState> {
        self.grass.read_states(gpu, &self.commands).unwrap()
    }

    /// The 4 control points (and width vectors) of each blade, as drawn.
    pub fn vertices(&self, gpu: &Gpu) -> Vec<BladeVertex> {
        self.vertices
            .read_back(gpu, &self.commands, self.blades.len() * 4)
            .unwrap()
    }

    /// The wind velocity's x, y and z face components.
    pub fn velocity(&self, gpu: &Gpu) -> [Vec<f32>; 3] {
        self.wind.read_velocity(gpu, &self.commands).unwrap()
    }

    pub fn destroy(self, gpu: &Gpu) {
        self.grass.destroy(gpu);
        self.vertices.destroy(gpu);
        self.wind.destroy(gpu);
        self.commands.destroy(gpu);
    }
}
