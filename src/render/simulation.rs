//! The simulating phase of a frame (paper section 5): wind step, then grass
//! step, as many fixed steps as the frame's time needs, recorded into the
//! frame's own command buffer ahead of the draw. The frame rate never
//! changes the physics: frame f shows simulated time start + f / fps,
//! reached in whole steps of the scene's dt.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::commands::Commands;
use crate::gpu::timing::{Phase, PhaseTimer};
use crate::gpu::{Buffer, Gpu};
use crate::render::grass_pass::GrassPass;
use crate::render::wind_pass::WindPass;
use crate::scene::Scene;
use crate::sim::GrassBlade;

pub struct Simulation {
    wind: WindPass,
    grass: GrassPass,
    dt: f32,
    steps_done: u64,
}

impl Simulation {
    /// Builds the wind solver for the scene and the grass dynamics writing
    /// into `vertices` (the renderer's blade vertex buffer, which must
    /// outlive this).
    pub fn new(
        gpu: &Gpu,
        commands: &Commands,
        scene: &Scene,
        blades: &[GrassBlade],
        vertices: &Buffer,
    ) -> Result<Self> {
        let grid = scene.wind_grid()?;
        let settings = scene.wind.settings();
        let dt = scene.wind.dt;
        let wind = WindPass::new(gpu, commands, grid, &settings)?;
        let grass =
            match GrassPass::new(gpu, commands, blades, vertices, wind.velocity(), &grid, dt) {
                Ok(g) => g,
                Err(e) => {
                    wind.destroy(gpu);
                    return Err(e);
                }
            };
        Ok(Self {
            wind,
            grass,
            dt,
            steps_done: 0,
        })
    }

    /// Steps needed so that the simulation reaches `time` (whole steps,
    /// rounded to the nearest; never backwards).
    pub fn steps_until(&self, time: f64) -> Result<u64> {
        let target = (time / self.dt as f64).round();
        if !target.is_finite() || target < 0.0 || target > u32::MAX as f64 {
            return Err(Error::InvalidInput(format!(
                "simulated time {time} s is out of range for a {} s step",
                self.dt
            )));
        }
        Ok((target as u64).saturating_sub(self.steps_done))
    }

    /// Records `steps` wind + grass steps into `cmd`, each phase of each
    /// step between timestamps when a timer is given.
    pub fn record(
        &mut self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        steps: u64,
        mut timer: Option<&mut PhaseTimer>,
    ) {
        for _ in 0..steps {
            let time = (self.steps_done as f64 * self.dt as f64) as f32;
            let span = timer.as_deref_mut().map(|t| t.begin(gpu, cmd, Phase::Wind));
            self.wind.record_step(gpu, cmd, time, self.dt);
            if let (Some(t), Some(span)) = (timer.as_deref(), span) {
                t.end(gpu, cmd, span);
            }
            let span = timer
                .as_deref_mut()
                .map(|t| t.begin(gpu, cmd, Phase::Grass));
            self.grass.record_step(gpu, cmd, 0);
            if let (Some(t), Some(span)) = (timer.as_deref(), span) {
                t.end(gpu, cmd, span);
            }
            self.steps_done += 1;
        }
    }

    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    pub fn substeps(&self) -> u32 {
        self.grass.substeps()
    }

    pub fn dt(&self) -> f32 {
        self.dt
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.wait_idle();
        self.grass.destroy(gpu);
        self.wind.destroy(gpu);
    }
}
