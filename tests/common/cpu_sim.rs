//! The CPU reference's simulation (src/model: the wind solver, the blade
//! dynamics and the canopy's drag, `canopy::coupled_step`), stepped as
//! `SimRig` steps the GPU's and checked against the same invariants
//! (`Figures::check`). The GPU's kernels are held to it step by step
//! (tests/wind_gpu.rs, tests/grass_gpu.rs, tests/canopy.rs, and
//! tests/motion.rs's trace), so a property it shows over minutes of
//! simulated time is proven once, without lavapipe running it.

use meadow::model::canopy;
use meadow::model::grass::{self, CapCounts};
use meadow::model::wind::{WindField, WindSettings};
use meadow::model::{BladeVertex, GrassBlade, GrassField};
use meadow::scene::{field, Scene};

use super::sim::Figures;

pub struct CpuRig {
    pub blades: Vec<GrassBlade>,
    settings: WindSettings,
    pub wind: WindField,
    pub grass: GrassField,
}

impl CpuRig {
    /// The scene's grass at rest and its wind, still: every blade steps
    /// (as on the GPU), whatever the coupling.
    pub fn new(scene: &Scene) -> Self {
        let rest = scene.field().unwrap();
        let blades = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed).unwrap();
        let settings = scene.wind_settings();
        let mut wind = WindField::new(scene.wind_grid().unwrap(), &settings);
        wind.canopy_unit = canopy::unit(&blades);
        let mut grass = GrassField::new(blades.clone(), scene.wind.dt)
            .unwrap()
            .with_colliders(scene.colliders.clone());
        grass.substeps = grass::substeps(&blades, scene.wind.dt).unwrap();
        Self {
            blades,
            settings,
            wind,
            grass,
        }
    }

    /// Runs `steps` wind + grass steps.
    pub fn run(&mut self, steps: u64) {
        for _ in 0..steps {
            canopy::coupled_step(&mut self.wind, &self.settings, &mut self.grass);
        }
    }

    pub fn steps_done(&self) -> u64 {
        self.grass.steps_done
    }

    /// Blade-steps at an angle cap so far.
    pub fn cap_counts(&self) -> CapCounts {
        self.grass.caps
    }

    /// The 4 control points (and width vectors) of each blade, as drawn.
    pub fn vertices(&self) -> Vec<BladeVertex> {
        self.grass.vertices()
    }

    /// Checks the wind and the blades (`Figures::check`).
    pub fn check(&self, figures: &mut Figures) {
        figures.check(
            self.steps_done(),
            &self.blades,
            &self.wind.vel,
            &self.grass.states,
            &self.vertices(),
        );
    }
}
