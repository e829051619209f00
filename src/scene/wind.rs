//! The scene's `[wind]` section beside its check: the grid's cells and
//! window, the solver, the inflow, sources, obstacles and turbulence. It
//! uses the checks' helpers (check.rs) and the wind model (src/model/wind).

use serde::{Deserialize, Serialize};

use super::check::{finite, in_range, path, positive, within, Check, FieldError, MAX_V_CYCLES};
use crate::model::wind::{
    Advection, Coupling, Gust, Inflow, Obstacle, PressureSolver, Sweep, Turbulence, WindSettings,
    WindSource, DEFAULT_CANOPY_DRAG, DEFAULT_JACOBI_ITERATIONS, DEFAULT_PRESSURE_TOLERANCE,
    DEFAULT_V_CYCLES, MAX_CELLS,
};

/// The wind of a scene (docs/method.md section 3): the grid spans the grass's
/// bounding box plus a margin, from the ground up to `height`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WindConfig {
    /// Cells along x, y (up), z: the paper's grid is 60 x 20 x 60.
    pub cells: [u32; 3],
    /// Height of the air the grid covers (m).
    pub height: f32,
    /// Horizontal margin around the grass (m).
    pub margin: f32,
    /// With `[grass.cover]`: the grid's horizontal extent [x, z] (m),
    /// centred under the camera, instead of the grass's box.
    #[serde(skip_serializing_if = "WindConfig::is_default_window")]
    pub window: [f32; 2],
    /// How the projection solves for the pressure: "multigrid" (default,
    /// converges) or "jacobi" (the paper's).
    pub solver: PressureSolver,
    /// Jacobi iterations per step with `solver = "jacobi"` (the paper's
    /// count is not given; 30 by default, docs/physics.md on what they reach).
    pub jacobi_iterations: u32,
    /// The most multigrid V-cycles a step runs with `solver = "multigrid"`.
    pub v_cycles: u32,
    /// With multigrid, the share of a step's rms divergence the
    /// projection may leave: the V-cycles stop once the residual is this
    /// small (0: always `v_cycles`).
    pub pressure_tolerance: f32,
    /// With multigrid, how the GPU runs a red-black sweep: "auto"
    /// (default: "fused" on a GPU, "split" on a CPU device), "fused"
    /// (both colours in one dispatch) or "split" (one a colour); the
    /// pressure is the same.
    pub sweep: Sweep,
    /// "one-way" (the paper's: the grass never touches the wind) or
    /// "two-way" (the canopy drag -C_d a |u| u slows the air in the grass).
    pub coupling: Coupling,
    /// C_d of the canopy drag with two-way coupling.
    pub canopy_drag: f32,
    /// "maccormack" (default: second order, bounded, keeps gusts) or
    /// "semi-lagrangian" (the paper's first-order step).
    pub advection: Advection,
    /// `{ intensity, length_scale, seed }`: a fluctuating wind everywhere
    /// (src/model/turbulence.rs); absent: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turbulence: Option<Turbulence>,
    /// Simulation step (s); the frame rate never changes it.
    pub dt: f32,
    #[serde(rename = "source", skip_serializing_if = "Vec::is_empty")]
    pub sources: Vec<WindSource>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inflow: Option<Inflow>,
    #[serde(rename = "obstacle", skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<Obstacle>,
}

impl Default for WindConfig {
    /// The paper's grid, still air.
    fn default() -> Self {
        Self {
            cells: [60, 20, 60],
            height: 3.0,
            margin: 1.5,
            window: DEFAULT_WIND_WINDOW,
            solver: PressureSolver::default(),
            jacobi_iterations: DEFAULT_JACOBI_ITERATIONS,
            v_cycles: DEFAULT_V_CYCLES,
            pressure_tolerance: DEFAULT_PRESSURE_TOLERANCE,
            sweep: Sweep::default(),
            coupling: Coupling::default(),
            canopy_drag: DEFAULT_CANOPY_DRAG,
            advection: Advection::default(),
            turbulence: None,
            dt: 1.0 / 60.0,
            sources: Vec::new(),
            inflow: None,
            obstacles: Vec::new(),
        }
    }
}

/// `wind.window`'s default (m): a 40 x 40 m square under the camera.
pub const DEFAULT_WIND_WINDOW: [f32; 2] = [40.0, 40.0];

impl WindConfig {
    fn is_default_window(window: &[f32; 2]) -> bool {
        *window == DEFAULT_WIND_WINDOW
    }

    /// Wind from the left (paper Fig. 10): a gusting inflow along +x.
    pub fn from_the_left(speed: f32) -> Self {
        Self {
            inflow: Some(Inflow {
                speed,
                heading: 0.0,
                gust: Gust {
                    amplitude: 0.5,
                    frequency: 0.3,
                    seed: 1,
                },
            }),
            ..Self::default()
        }
    }

    /// What drives the wind, but the colliders (which the scene holds
    /// beside its wind: `Scene::wind_settings`).
    pub fn settings(&self) -> WindSettings {
        WindSettings {
            sources: self.sources.clone(),
            inflow: self.inflow,
            obstacles: self.obstacles.clone(),
            colliders: Vec::new(),
            solver: self.solver,
            jacobi_iterations: self.jacobi_iterations,
            v_cycles: self.v_cycles,
            pressure_tolerance: self.pressure_tolerance,
            sweep: self.sweep,
            coupling: self.coupling,
            canopy_drag: self.canopy_drag,
            advection: self.advection,
            turbulence: self.turbulence,
            terrain: Default::default(),
            moving_window: false,
        }
    }
}

impl WindConfig {
    /// With `[grass.cover]` the wind grid is a window that follows the camera
    /// in whole cells, its air shifted with it (src/model/wind/window.rs):
    /// what is fixed to the grid's sides or cells would move with it.
    pub(super) fn check_moving_window(&self) -> Check {
        if self.inflow.is_some_and(|i| i.gust.amplitude != 0.0) {
            return Err(FieldError::new(
                "inflow.gust",
                "enters at the wind window's upwind side, which follows the camera with [grass.cover]; remove the gust and use wind.turbulence, which is alive everywhere",
            ));
        }
        if !self.obstacles.is_empty() {
            return Err(FieldError::new(
                "obstacle",
                format!(
                    "{} obstacles with [grass.cover]: its wind window follows the camera and holds no fixed solid cells yet; remove the [[wind.obstacle]] or the cover",
                    self.obstacles.len()
                ),
            ));
        }
        Ok(())
    }

    pub fn check(&self) -> Check {
        for (a, &n) in self.cells.iter().enumerate() {
            in_range(&format!("cells[{a}]"), n, 1..=4096)?;
        }
        let cells: u64 = self.cells.iter().map(|&n| n as u64).product();
        if cells > MAX_CELLS {
            return Err(FieldError::new(
                "cells",
                format!("{cells} cells is not allowed, use at most {MAX_CELLS}"),
            ));
        }
        positive("height", self.height, 1000.0)?;
        within("margin", self.margin, 0.0..=1000.0, "0..=1000 m")?;
        positive("window[0]", self.window[0], 10_000.0)?;
        positive("window[1]", self.window[1], 10_000.0)?;
        in_range("jacobi_iterations", self.jacobi_iterations, 0..=10_000)?;
        in_range("v_cycles", self.v_cycles, 1..=MAX_V_CYCLES)?;
        within(
            "pressure_tolerance",
            self.pressure_tolerance,
            0.0..=0.5,
            "0..=0.5 (the share of the divergence left; 0 runs every V-cycle)",
        )?;
        within("canopy_drag", self.canopy_drag, 0.0..=10.0, "0..=10")?;
        positive("dt", self.dt, 0.1)?;
        for (i, s) in self.sources.iter().enumerate() {
            source(s).map_err(|e| e.at(&format!("source[{i}]")))?;
        }
        if let Some(inflow) = &self.inflow {
            finite("inflow.speed", &[inflow.speed])?;
            within(
                "inflow.heading",
                inflow.heading,
                -360.0..=360.0,
                "-360..=360 degrees (0 blows towards +x, 90 towards +z)",
            )?;
            if inflow.speed.abs() > 100.0 {
                return Err(FieldError::new(
                    "inflow.speed",
                    format!("{} is not allowed, use -100..=100 m/s", inflow.speed),
                ));
            }
            gust(&inflow.gust).map_err(|e| e.at("inflow.gust"))?;
        }
        for (i, o) in self.obstacles.iter().enumerate() {
            obstacle(o).map_err(|e| e.at(&format!("obstacle[{i}]")))?;
        }
        if let Some(t) = &self.turbulence {
            turbulence(t, self.inflow.is_some()).map_err(|e| e.at("turbulence"))?;
        }
        Ok(())
    }
}

/// What can be checked without the grid (the length scale against the
/// cells: `Scene::wind_grid`).
fn turbulence(t: &crate::model::wind::Turbulence, inflow: bool) -> Check {
    positive("intensity", t.intensity, 2.0)?;
    positive("length_scale", t.length_scale, 100_000.0)?;
    if let Some(finest) = t.finest_wavelength {
        positive("finest_wavelength", finest, 100_000.0)?;
    }
    match t.speed {
        Some(speed) => positive("speed", speed, 100.0),
        None if inflow => Ok(()),
        None => Err(FieldError::new(
            "speed",
            "missing: without an inflow it is needed, as the intensity is sigma_u over this speed; give it in m/s (above 0 and at most 100)",
        )),
    }
}

fn gust(g: &crate::model::wind::Gust) -> Check {
    within("amplitude", g.amplitude, 0.0..=10.0, "0..=10")?;
    within("frequency", g.frequency, 0.0..=100.0, "0..=100 Hz")?;
    Ok(())
}

fn source(s: &WindSource) -> Check {
    finite("position", &s.position.to_array())?;
    finite("direction", &s.direction.to_array())?;
    if s.direction.length() < 1e-6 {
        return Err(FieldError::new(
            "direction",
            "is zero, give the direction the source pushes the air",
        ));
    }
    finite("strength", &[s.strength])?;
    if s.strength.abs() > 1000.0 {
        return Err(FieldError::new(
            "strength",
            format!("{} is not allowed, use -1000..=1000 m/s^2", s.strength),
        ));
    }
    positive("radius", s.radius, 10_000.0)?;
    finite("rotation_speed", &[s.rotation_speed])?;
    path(&s.path, s.path_speed)?;
    gust(&s.gust).map_err(|e| e.at("gust"))?;
    if let Some(off) = s.off_after {
        if !(off.is_finite() && off >= 0.0) {
            return Err(FieldError::new(
                "off_after",
                format!("{off} is not allowed, use a time of 0 s or more"),
            ));
        }
    }
    Ok(())
}

fn obstacle(o: &Obstacle) -> Check {
    match *o {
        Obstacle::Box { min, max } => {
            finite("min", &min.to_array())?;
            finite("max", &max.to_array())?;
            if min.cmpge(max).any() {
                return Err(FieldError::new(
                    "max",
                    format!("{max} is not above min {min} on every axis"),
                ));
            }
        }
        Obstacle::Sphere { center, radius } => {
            finite("center", &center.to_array())?;
            positive("radius", radius, 10_000.0)?;
        }
        Obstacle::Cylinder {
            base,
            radius,
            height,
        } => {
            finite("base", &base.to_array())?;
            positive("radius", radius, 10_000.0)?;
            positive("height", height, 10_000.0)?;
        }
    }
    Ok(())
}
