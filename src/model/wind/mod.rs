//! CPU reference of the wind solver (paper section 3.2; docs/method.md section 3):
//! inviscid, incompressible Navier-Stokes on a grid, one step =
//! add source forces -> advection (MacCormack's corrector on the paper's
//! semi-Lagrangian step by default, or that step alone) -> divergence ->
//! pressure (multigrid V-cycles by default, src/model/multigrid.rs, or the
//! paper's Jacobi iterations) -> subtract the pressure gradient; with
//! turbulence (src/model/turbulence.rs) its field is added on top (before
//! the projection among solid cells).
//!
//! This file holds the field (`WindField`) and its step. Its children, each
//! using only this file's items and each other's through it:
//! - `grid.rs`: the grid, its cells and faces and how they are numbered;
//! - `drive.rs`: what drives the wind (inflow, gusts, sources, obstacles);
//! - `settings.rs`: the `[wind]` settings and their check;
//! - `faces.rs`: what each cell and face is (solid, ground, free, wall,
//!   inflow, buried) and the classification a grid alone gets;
//! - `sampling.rs`, `advection.rs`, `projection.rs`: the field's reading,
//!   kernel 2, and kernels 3-5, as `impl WindField` blocks;
//! - `window.rs`: the window that follows a cover's camera.
//!
//! A staggered (MAC) grid: the x component lives on the cells' x faces, y on
//! y faces, z on z faces, pressure at cell centres. Divergence and gradient
//! are then compact differences and the projection converges to a
//! divergence-free field as the Jacobi count grows.
//!
//! Boundaries (ours, docs/method.md): the grid's floor and solid cells (the
//! obstacles', and those under the ground's height field) are no-through
//! (their faces hold zero); the top is free-slip (no flow through it,
//! tangential flow free); the four sides are open: the pressure outside
//! is zero, so wind leaves the domain. An inflow's entry sides (one or two,
//! from its heading) hold their faces at its velocity across them; a side
//! along it is free-slip (a wind tunnel: what enters leaves through the
//! far sides).
//!
//! The GPU compute shaders in glsl/wind/ follow this file kernel by kernel.

use glam::Vec3;

mod advection;
mod drive;
mod faces;
mod grid;
mod projection;
mod sampling;
mod settings;
mod window;

use super::contact::ColliderState;
use super::multigrid::{Multigrid, Solve, Work};
pub use super::path::{along_path, MAX_PATH_POINTS};
pub use super::turbulence::Turbulence;
use super::turbulence::TurbulenceField;
use crate::interface::TurbulenceMode;
pub use drive::*;
use faces::multigrid_of;
pub use faces::{voxelised, Cells, Classification, FaceKind};
pub use grid::*;
pub use settings::*;

/// The solver state on the CPU.
#[derive(Clone, Debug)]
pub struct WindField {
    pub grid: WindGrid,
    /// Velocity components on their faces: [x, y, z].
    pub vel: [Vec<f32>; 3],
    pub pressure: Vec<f32>,
    /// The pressure of the step before the last (the multigrid's
    /// extrapolated start, `Multigrid::solve`).
    pub pressure_before: Vec<f32>,
    pub divergence: Vec<f32>,
    pub solid: Vec<bool>,
    /// The solid cells that lie under the ground (not an obstacle's).
    pub ground: Vec<bool>,
    /// What each velocity sample is: free, wall, inflow or buried (fixed
    /// per scene, or per inflow heading).
    pub faces: [Vec<FaceKind>; 3],
    /// The grass's frontal area in each cell, in counts of `canopy_unit`
    /// m^2, laid by the last grass step (src/model/canopy.rs); all zero
    /// unless the coupling is two-way.
    pub canopy: Vec<u32>,
    /// Square metres per count of `canopy` (0 until grass is coupled).
    pub canopy_unit: f32,
    /// The multigrid hierarchy of this grid's faces, and its coarse levels' storage.
    pub multigrid: Multigrid,
    /// The turbulence's modes (None: no turbulence).
    pub turbulence: Option<TurbulenceField>,
    /// What the last step added of the turbulence on each face, taken off
    /// again before the next (zero without turbulence).
    pub turbulence_added: [Vec<f32>; 3],
    /// The turbulence's modes finer than the grid as the last step left
    /// them (`TurbulenceField::subgrid_records`), which `felt` adds at a
    /// blade's tip; empty without.
    pub subgrid_turbulence: Vec<TurbulenceMode>,
    multigrid_work: Work,
    /// What the last step's multigrid pressure solve did (default until
    /// one ran).
    pub last_solve: Solve,
    pub time: f32,
}

impl WindField {
    /// Voxelises the obstacles and the ground and classifies every face,
    /// once: a cell is solid where its centre lies inside an obstacle or
    /// under the ground (a staircase whose treads lie at the ground's
    /// height rounded to the nearest face; docs/method.md).
    pub fn new(grid: WindGrid, settings: &WindSettings) -> Self {
        let (ground, solid) = voxelised(&grid, settings);
        let mut field = Self {
            vel: [0, 1, 2].map(|a| {
                let d = grid.face_dims(a);
                vec![0.0; (d.x * d.y * d.z) as usize]
            }),
            pressure: vec![0.0; grid.cell_count()],
            pressure_before: vec![0.0; grid.cell_count()],
            divergence: vec![0.0; grid.cell_count()],
            canopy: vec![0; grid.cell_count()],
            canopy_unit: 0.0,
            solid,
            ground,
            faces: [Vec::new(), Vec::new(), Vec::new()],
            multigrid: Multigrid::default(),
            multigrid_work: Work::default(),
            last_solve: Solve::default(),
            turbulence: settings.turbulence.map(|t| {
                TurbulenceField::new(&t, grid.cells, grid.cell, settings.turbulence_walls())
            }),
            turbulence_added: [0, 1, 2].map(|a| {
                let d = grid.face_dims(a);
                vec![0.0; (d.x * d.y * d.z) as usize]
            }),
            subgrid_turbulence: Vec::new(),
            grid,
            time: 0.0,
        };
        field.classify_faces(settings.inflow.as_ref());
        // The modes finer than the grid as they start (the GPU's wind pass
        // hands the same to a trace's first sample); the first step's
        // forces take them on from there.
        if let Some(turbulence) = &field.turbulence {
            field.subgrid_turbulence = turbulence.subgrid_records(settings.turbulence_sigma());
        }
        if let Some(inflow) = settings
            .inflow
            .filter(|i| i.is_oblique() || !settings.terrain.is_flat())
        {
            field.start_with(&inflow);
        }
        field
    }

    /// The air at the inflow's mean velocity on every free face (and the
    /// ghost values under the ground), the first projection then turning
    /// it around the terrain and obstacles. Started from rest instead, an
    /// oblique inflow leaves the first projection's potential flow, which
    /// leaves the open exit sides at right angles (zero pressure there),
    /// for the inflow to flush out over several crossings of the grid;
    /// over terrain the ground's staircase would start the air in
    /// eddies. A wind along an axis over flat ground starts from rest, as
    /// it always has (its first projection gives the uniform flow).
    fn start_with(&mut self, inflow: &Inflow) {
        let mean = inflow.mean_velocity();
        for axis in [0, 2] {
            for (v, kind) in self.vel[axis].iter_mut().zip(&self.faces[axis]) {
                if matches!(kind, FaceKind::Free | FaceKind::Buried) {
                    *v = mean[axis];
                }
            }
        }
    }

    /// Classifies every face for `inflow` (its entry, exit and along
    /// sides) and builds the multigrid hierarchy of the free faces; a
    /// wind whose inflow turns calls it again (the viewer's arrows).
    /// Returns whether any face changed its kind.
    pub fn classify_faces(&mut self, inflow: Option<&Inflow>) -> bool {
        let cells = Cells {
            grid: &self.grid,
            solid: &self.solid,
            ground: &self.ground,
        };
        let faces = cells.face_kinds(inflow);
        if faces == self.faces && !self.multigrid.levels.is_empty() {
            return false;
        }
        self.multigrid = multigrid_of(&self.grid, &faces);
        self.faces = faces;
        self.multigrid_work = Work::default();
        true
    }

    /// Whether grass slows this wind: two-way coupling with a drag, and
    /// grass coupled (a canopy unit set).
    pub fn is_coupled(&self, settings: &WindSettings) -> bool {
        settings.effective_canopy_drag() > 0.0 && self.canopy_unit > 0.0
    }

    /// One full step of length `dt` (s): the mean wind's (the
    /// turbulence the last step added taken off first), then this step's
    /// turbulence added.
    pub fn step(&mut self, settings: &WindSettings, dt: f32) {
        self.take_off_turbulence();
        self.add_forces(settings, dt);
        let drag = if self.is_coupled(settings) {
            settings.effective_canopy_drag()
        } else {
            0.0
        };
        self.advect(dt, drag, settings.inflow.as_ref(), settings.advection);
        // Among solids the modes' flow runs into them: the projection
        // turns it around them as it turns the mean wind. Without, the
        // modes are divergence-free as they are, and added after it.
        let among_solids = self.solid.contains(&true);
        if among_solids {
            self.add_turbulence(settings, dt);
        }
        self.compute_divergence();
        match settings.solver {
            PressureSolver::Jacobi => self.solve_pressure(settings.jacobi_iterations),
            PressureSolver::Multigrid => {
                self.solve_pressure_multigrid(settings.v_cycles, settings.pressure_tolerance);
            }
        }
        self.subtract_gradient();
        self.free_slip_under_ground();
        if !among_solids {
            self.add_turbulence(settings, dt);
        }
        self.time += dt;
    }

    /// The free and buried faces without what the last step's turbulence
    /// added (in the GPU's forces kernel).
    fn take_off_turbulence(&mut self) {
        for axis in 0..3 {
            for (idx, kind) in self.faces[axis].iter().enumerate() {
                if matches!(kind, FaceKind::Free | FaceKind::Buried) {
                    self.vel[axis][idx] -= self.turbulence_added[axis][idx];
                }
            }
        }
    }

    /// Kernel 7, with turbulence (src/model/turbulence.rs): the modes
    /// carried on by this step, every free and inflow face gains the
    /// field at the step's end, and keeps what it gained (an inflow face
    /// is set anew by the next step's forces). A buried face holds the air
    /// above's value, turbulence and all (`free_slip_under_ground`).
    pub fn add_turbulence(&mut self, settings: &WindSettings, dt: f32) {
        let (Some(field), Some(_)) = (&mut self.turbulence, &settings.turbulence) else {
            return;
        };
        field.advance(
            settings.turbulence_convection(),
            settings.turbulence_sigma(),
            dt,
        );
        self.add_turbulence_now(settings);
    }

    /// Every face not a wall gains the turbulence's field as its modes
    /// stand now, and keeps what it gained (`turbulence_added`); so do the
    /// walls on the grid's sides across an axis the modes are not
    /// mirrored across, before a cell of air (a moving window's sides
    /// along the wind): there
    /// the field's normal component is not zero, and holding it at zero
    /// would leave a layer of cells diverging. The mean flow stays
    /// walled: the next step's forces set those faces to zero again.
    pub(super) fn add_turbulence_now(&mut self, settings: &WindSettings) {
        let (Some(field), Some(_)) = (&self.turbulence, &settings.turbulence) else {
            return;
        };
        let records = field.records(settings.turbulence_sigma());
        self.subgrid_turbulence = field.subgrid_records(settings.turbulence_sigma());
        let (grid, solid) = (&self.grid, &self.solid);
        let n = grid.cells;
        for axis in 0..3 {
            // A side's face before a cell of air (not one walled by an
            // obstacle or the ground at the side).
            let open_side = |f: [u32; 3]| {
                let mut c = f;
                c[axis] = c[axis].min(n[axis] - 1);
                axis != 1
                    && !field.is_mirrored(axis)
                    && (f[axis] == 0 || f[axis] == n[axis])
                    && !solid[grid.cell_index(c[0], c[1], c[2])]
            };
            let field_here = field.on_faces(&records, axis, grid.face_dims(axis));
            for (idx, f) in self.grid.each_face(axis) {
                let kind = self.faces[axis][idx];
                if kind == FaceKind::Buried || (kind == FaceKind::Wall && !open_side(f)) {
                    self.turbulence_added[axis][idx] = 0.0;
                    continue;
                }
                let u = field_here[idx] as f32;
                self.vel[axis][idx] += u;
                self.turbulence_added[axis][idx] = u;
            }
        }
    }

    /// Kernel 6, with terrain: each buried face (a horizontal component
    /// between two cells under the ground) takes the value of the first
    /// free face above it in its column. Only the samplers read these
    /// ghost values (advection's trace and a blade tip's wind): without
    /// them the zeros under the ground would be interpolated into the air
    /// above the staircase, a numerical no-slip wall that thickens
    /// downwind and lifts the flow over a hill (docs/physics.md, wind over
    /// a ridge). No pressure, divergence or projection term reads them.
    pub fn free_slip_under_ground(&mut self) {
        for axis in [0, 2] {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Buried {
                    continue;
                }
                self.vel[axis][idx] = (j + 1..self.grid.cells.y)
                    .map(|up| self.grid.face_index(axis, i, up, k))
                    .find(|&above| self.faces[axis][above] == FaceKind::Free)
                    .map_or(0.0, |above| self.vel[axis][above]);
            }
        }
    }

    /// Kernel 1: every free face gains dt * f of every source; inflow faces
    /// take the inflow velocity; walls hold zero.
    ///
    /// The colliders are moving obstacles (ours), by direct forcing: a free
    /// face inside one takes its velocity (the first in scene order that
    /// holds it). The projection then turns the air around it, as around
    /// the fixed solids; unlike theirs, these faces stay free, so the
    /// multigrid hierarchy is built once. What is left flowing through a
    /// collider is measured in tests/wind_cpu.rs (docs/physics.md).
    pub fn add_forces(&mut self, settings: &WindSettings, dt: f32) {
        let t = self.time;
        let moving: Vec<ColliderState> = settings.colliders.iter().map(|c| c.at(t)).collect();
        let sources: Vec<(Vec3, Vec3, f32, f32)> = settings
            .sources
            .iter()
            .map(|s| {
                let (p, d, st) = s.at(t);
                (p, d, st, s.radius)
            })
            .collect();
        let inflow = settings.inflow.as_ref();
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                match self.faces[axis][idx] {
                    FaceKind::Wall => self.vel[axis][idx] = 0.0,
                    // Holds the ghost value `free_slip_under_ground` gave it.
                    FaceKind::Buried => {}
                    FaceKind::Inflow => {
                        let inflow = inflow.expect("inflow faces exist only with an inflow");
                        let x = self.grid.face_position(axis, i, j, k);
                        self.vel[axis][idx] = inflow.velocity_at(axis, &self.grid, x, t);
                    }
                    FaceKind::Free => {
                        let x = self.grid.face_position(axis, i, j, k);
                        let mut a = 0.0;
                        for &(p, dir, strength, radius) in &sources {
                            a += strength * dir[axis] * falloff(x.distance(p), radius);
                        }
                        self.vel[axis][idx] += dt * a;
                        if let Some(c) = moving.iter().find(|c| c.distance(x).0 < 0.0) {
                            self.vel[axis][idx] = c.velocity[axis];
                        }
                    }
                }
            }
        }
    }
}
