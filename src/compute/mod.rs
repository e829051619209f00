//! The simulating phase of a frame (paper section 4 and 3.2): the wind
//! solver and the grass dynamics on GPU compute. One simulation step is a
//! wind step and then a grass step; the frame recorder records as many as
//! the frame's time needs, ahead of the draw. The frame rate never changes
//! the physics: frame f shows simulated time start + f / fps, reached in
//! whole steps of the scene's dt. It writes the blade buffer it is handed
//! and knows nothing of the rendering.

pub mod collider_bins;
mod colliders;
pub mod cover_dynamics;
pub mod cover_tiles;
pub mod grass_pass;
mod place_order;
pub mod step_pace;
pub mod wind_pass;

use crate::error::{Error, Result};
use ash::vk;

use crate::gpu::{Access, Buffer, CommandPool, Gpu, Recording};
use crate::model::collider::Collider;
use crate::model::terrain::Terrain;
use crate::model::{canopy, GrassBlade};
use crate::scene::Scene;

pub use cover_dynamics::CoverDynamics;
pub use cover_tiles::CoverTilePass;
pub use grass_pass::GrassPass;
pub use step_pace::StepPace;
pub use wind_pass::WindPass;

pub struct Simulation {
    /// None where the scene's only grass is a cover (no patch blades to
    /// step): the wind runs alone.
    grass: Option<GrassPass>,
    /// The cover's blades within its `simulate_radius` of the camera
    /// (`[grass.cover]` with a radius above zero).
    cover: Option<CoverDynamics>,
    wind: WindPass,
    dt: f32,
    steps_done: u64,
}

impl Simulation {
    /// Builds the wind solver for the scene and the grass dynamics writing
    /// into `vertices` (the blade buffer; the grass pass's sets hold it).
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        scene: &Scene,
        blades: &[GrassBlade],
        vertices: &Buffer,
    ) -> Result<Self> {
        let grid = scene.wind_grid()?;
        let settings = scene.wind_settings();
        let dt = scene.wind.dt;
        let wind = WindPass::new(gpu, commands, grid, &settings, canopy::unit(blades))?;
        let grass = (!blades.is_empty())
            .then(|| {
                GrassPass::new(
                    gpu,
                    commands,
                    blades,
                    vertices,
                    &wind.grass_input(),
                    &scene.colliders,
                    dt,
                )
            })
            .transpose()?;
        let cover = match &scene.grass.cover {
            Some(c) if c.simulate_radius() > 0.0 => {
                let (eye, _) = scene.camera.at(0.0);
                let setup = cover_dynamics::CoverDynamicsSetup {
                    cover: c,
                    seed: crate::scene::cover::seed32(c.seed.unwrap_or(scene.seed)),
                    grass: &scene.grass,
                    dt,
                    camera: glam::Vec2::new(eye.x, eye.z),
                    terrain: &scene.ground.terrain(),
                    colliders: &scene.colliders,
                };
                Some(CoverDynamics::new(
                    gpu,
                    commands,
                    setup,
                    &wind.grass_input(),
                )?)
            }
            _ => None,
        };
        Ok(Self {
            grass,
            cover,
            wind,
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

    /// Simulated time (s) once `steps` more steps are done: what the
    /// blade buffer shows then.
    pub fn time_after(&self, steps: u64) -> f64 {
        (self.steps_done + steps) as f64 * self.dt as f64
    }

    /// Records the wind half of the next step (paper section 3.2).
    pub fn record_wind_step(&mut self, rec: &Recording) {
        self.wind
            .record_step(rec, self.time_after(0) as f32, self.dt);
    }

    /// Records the grass half of the next step (paper section 4), which
    /// completes it.
    pub fn record_grass_step(&mut self, rec: &Recording) {
        let end_time = crate::model::contact::step_end_time(self.steps_done, self.dt);
        if let Some(grass) = &self.grass {
            grass.record_step(rec, 0, end_time);
        }
        if let Some(cover) = &mut self.cover {
            cover.record_step(rec, end_time);
        }
        self.steps_done += 1;
    }

    /// Follows a camera at `eye_xz` (x, z) with what `[grass.cover]`
    /// keeps around it: the wind window, moved in whole cells once the eye
    /// is a cell or more from its centre (`WindGrid::window_shift`), the
    /// air with it, the grass sampling the moved grid; and the tiles whose
    /// blades the paper's dynamics step (`CoverDynamics::record_follow`).
    /// Records nothing for a scene without a cover.
    pub fn record_follow(&mut self, rec: &Recording, eye_xz: glam::Vec2) -> Result<()> {
        if self.wind.follows_camera() {
            let by = self.wind.grid.window_shift(eye_xz);
            if by != glam::IVec2::ZERO {
                self.wind.record_shift(rec, by)?;
                let origin = self.wind.grid.origin;
                if let Some(grass) = &mut self.grass {
                    grass.set_wind_origin(origin);
                }
                if let Some(cover) = &mut self.cover {
                    cover.set_wind_origin(origin);
                }
            }
        }
        if let Some(cover) = &mut self.cover {
            cover.record_follow(rec, eye_xz)?;
        }
        Ok(())
    }

    /// The cover's blades the paper's dynamics step near the camera (None
    /// without a cover or with a `simulate_radius` of 0).
    pub fn cover_dynamics(&self) -> Option<&CoverDynamics> {
        self.cover.as_ref()
    }

    /// Records `steps` whole steps, untimed.
    pub fn record_steps(&mut self, rec: &Recording, steps: u64) {
        for _ in 0..steps {
            self.record_wind_step(rec);
            self.record_grass_step(rec);
        }
    }

    /// The colliders from the next recorded step on, for the grass they
    /// press and the air they push alike (the viewer's ball): written in
    /// the command buffer, no upload. A simulation made without colliders
    /// refuses any, and changes neither pass.
    pub fn set_colliders(&mut self, colliders: &[Collider]) -> Result<()> {
        if let Some(grass) = &mut self.grass {
            grass.set_colliders(colliders)?;
        }
        if let Some(cover) = &mut self.cover {
            cover.set_colliders(colliders)?;
        }
        self.wind.set_colliders(colliders)
    }

    /// Blade-steps at an angle cap so far (docs/physics.md).
    pub fn cap_counts(
        &self,
        gpu: &Gpu,
        commands: &CommandPool,
    ) -> Result<crate::model::grass::CapCounts> {
        match &self.grass {
            Some(grass) => grass.read_caps(gpu, commands, self.steps_done),
            None => Ok(Default::default()),
        }
    }

    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    /// The grass step's substeps: the patches', or else the cover's
    /// kept blades' (0 with neither).
    pub fn substeps(&self) -> u32 {
        match (&self.grass, &self.cover) {
            (Some(g), _) => g.substeps(),
            (None, Some(c)) => c.grass().substeps(),
            (None, None) => 0,
        }
    }

    pub fn dt(&self) -> f32 {
        self.dt
    }

    pub fn wind(&self) -> &WindPass {
        &self.wind
    }

    pub fn wind_mut(&mut self) -> &mut WindPass {
        &mut self.wind
    }

    /// The patches' grass pass; None where the only grass is a cover.
    pub fn grass(&self) -> Option<&GrassPass> {
        self.grass.as_ref()
    }
}

/// The terrain as glsl/common/terrain.glsl reads it (`Terrain::gpu_words`):
/// its header, then its words (one unused word where it has none), named
/// `name`.
pub fn terrain_buffer(
    gpu: &Gpu,
    commands: &CommandPool,
    terrain: &Terrain,
    name: &str,
) -> Result<Buffer> {
    let (header, words) = terrain.gpu_words();
    let mut bytes = bytemuck::bytes_of(&header).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(if words.is_empty() {
        &[0.0f32][..]
    } else {
        &words
    }));
    Buffer::with_data(
        gpu,
        commands,
        name,
        &bytes,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        Access::COMPUTE_READ,
    )
}
