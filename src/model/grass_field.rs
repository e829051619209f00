//! A whole field of blades stepping together on the CPU, with the colliders
//! moving through it: what the GPU grass kernel does, one invocation per
//! blade (src/model/grass.rs steps one blade, src/model/contact.rs resolves its
//! contacts).

use glam::Vec3;

use crate::error::Result;
use crate::model::blade::BladeVertex;
use crate::model::contact;
use crate::model::grass::{
    pressed_pose, substeps, vertices, CapCounts, GrassBlade, GrassState, Pose,
};

/// A whole field of blades stepping together: what the GPU kernel does,
/// one invocation per blade.
#[derive(Clone, Debug)]
pub struct GrassField {
    pub blades: Vec<GrassBlade>,
    pub states: Vec<GrassState>,
    pub substeps: u32,
    pub dt: f32,
    pub caps: CapCounts,
    /// What moves through the meadow (src/model/contact.rs).
    pub colliders: Vec<contact::Collider>,
    /// Each blade's pressed state (`contact::Press`).
    pub pressed: Vec<contact::Press>,
    pub steps_done: u64,
}

impl GrassField {
    pub fn new(blades: Vec<GrassBlade>, dt: f32) -> Result<Self> {
        let substeps = substeps(&blades, dt)?;
        Ok(Self {
            states: vec![GrassState::default(); blades.len()],
            pressed: vec![contact::Press::default(); blades.len()],
            blades,
            substeps,
            dt,
            caps: CapCounts::default(),
            colliders: Vec::new(),
            steps_done: 0,
        })
    }

    /// The same field with `colliders` moving through it.
    pub fn with_colliders(mut self, colliders: Vec<contact::Collider>) -> Self {
        self.colliders = colliders;
        self
    }

    /// Advances every blade one step, each with the wind `wind_at` gives at
    /// its current tip.
    pub fn step(&mut self, wind_at: impl FnMut(Vec3) -> Vec3) {
        self.step_each(wind_at, |_, _, _| {});
    }

    /// As `step`, handing `after` each blade, its new state and the wind it
    /// felt (as sampled, before the guard) once it has stepped.
    pub fn step_each(
        &mut self,
        mut wind_at: impl FnMut(Vec3) -> Vec3,
        mut after: impl FnMut(&GrassBlade, &GrassState, Vec3),
    ) {
        let time = contact::step_end_time(self.steps_done, self.dt);
        let colliders: Vec<contact::ColliderState> =
            self.colliders.iter().map(|c| c.at(time)).collect();
        let decay = contact::press_decay(self.dt);
        for ((blade, state), press) in self
            .blades
            .iter()
            .zip(&mut self.states)
            .zip(&mut self.pressed)
        {
            let tip = pressed_pose(blade, state.angle, press.pressed).points[3];
            let wind = wind_at(tip);
            let pressed = press.next(self.dt, decay);
            let near = contact::near_blade(&colliders, blade.rest_point(0), contact::reach(blade));
            let touched =
                contact::step_touching(blade, state, wind, self.dt, self.substeps, pressed, &near);
            *press = contact::Press {
                pressed,
                touched: touched as u32 as f32,
            };
            self.caps.count(state);
            after(blade, state, wind);
        }
        self.steps_done += 1;
    }

    pub fn poses(&self) -> impl Iterator<Item = Pose> + '_ {
        self.blades
            .iter()
            .zip(&self.states)
            .zip(&self.pressed)
            .map(|((b, s), p)| pressed_pose(b, s.angle, p.pressed))
    }

    /// The vertex buffer the renderer would draw.
    pub fn vertices(&self) -> Vec<BladeVertex> {
        self.blades
            .iter()
            .zip(self.poses())
            .flat_map(|(b, p)| vertices(b, &p))
            .collect()
    }
}
