//! One wind step recorded: the push constants, each kernel's declared
//! uses, the kernels in order with their barriers, the turbulence's modes
//! uploaded, and the window's shift.

use super::*;

impl WindPass {
    /// The push constants of a step at `time`, the pressure solve's
    /// halves and the multigrid level and colour a kernel works on left at
    /// zero.
    fn push(&self, time: f32, dt: f32) -> WindPush {
        let inflow = self.settings.inflow;
        let phases = inflow.map(|i| i.gust.phases()).unwrap_or_default();
        // The canopy drag's C_d (0: none) and what one count on each side
        // of a face adds to its frontal area per volume, as
        // `WindField::canopy_density_per_count` computes it.
        let (drag, per_count) = if self.coupled() {
            let cell = self.grid.cell;
            (
                self.settings.effective_canopy_drag(),
                self.canopy_unit * 0.5 / cell.element_product(),
            )
        } else {
            (0.0, 0.0)
        };
        let multigrid = self.settings.solver == PressureSolver::Multigrid;
        WindPush {
            grid: grid_params(&self.grid, self.face_count),
            time,
            dt,
            canopy_drag: drag,
            area_per_count: per_count,
            source_count: self.settings.sources.len() as u32,
            pressure_read: 0,
            pressure_result: if multigrid {
                0
            } else {
                self.settings.jacobi_iterations % 2
            },
            pressure_tolerance: self.settings.pressure_tolerance,
            inflow_speed: inflow.map_or(0.0, |i| i.speed),
            gust_amplitude: inflow.map_or(0.0, |i| i.gust.amplitude),
            gust_frequency: inflow.map_or(0.0, |i| i.gust.frequency),
            inflow_heading: inflow.map_or(0.0, |i| i.heading.to_radians()),
            gust_phases: phases,
            collider_count: self.settings.colliders.len() as u32,
            coarse_cells: self.coarse_cells,
            ..WindPush::default()
        }
    }

    /// What `kernel` reads and writes, as build.rs reflected it from
    /// glsl/wind/*.comp: the recording derives the barriers between the
    /// kernels, and against the grass step's reads of the velocity and
    /// writes of the canopy, from it.
    fn kernel_uses(&self, kernel: usize) -> Vec<BufferUse> {
        WIND_KERNELS[kernel].buffer_uses(0, &self.buffers.bound())
    }

    /// Kernel `kernel` made for level `level` (`LEVEL_KERNELS` are made
    /// for level 0 and for the coarse levels; the others for any).
    fn level_kernel(&self, kernel: usize, level: u32) -> &Pipeline {
        let made = match LEVEL_KERNELS.iter().position(|&k| k == kernel) {
            Some(i) if level == 0 => &self.finest_kernels[i],
            _ => &self.kernels[kernel],
        };
        made.as_ref()
            .expect("a step records only the kernels its settings run (`runs_kernel`)")
    }

    /// The forces kernel with the code for what this step has: sources,
    /// colliders, both or neither (the same arithmetic on every face).
    fn forces_kernel(&self) -> &Pipeline {
        let sources = !self.settings.sources.is_empty();
        let colliders = !self.collider_records.is_empty();
        match (sources, colliders) {
            (true, true) => self.level_kernel(FORCES, 0),
            (true, false) => &self.forces_without[0],
            (false, true) => &self.forces_without[1],
            (false, false) => &self.forces_without[2],
        }
    }

    /// Records one solver step at simulation time `time`: each kernel
    /// declares what it touches (`kernel_uses`). Ends with the new velocity
    /// (copy A) written by compute; a reader declares its use. Steps the
    /// turbulence's modes on: record the steps in order.
    pub fn record_step(&mut self, rec: &Recording, time: f32, dt: f32) {
        let before = rec.dispatches();
        let modes = self.turbulence_records(dt);
        let face_groups = self.face_count.div_ceil(WIND_GROUP);
        let cell_groups = self.cell_count.div_ceil(WIND_GROUP);
        let step = self.push(time, dt);
        // A kernel bound with its push constants: `read` the Jacobi half
        // it reads, then the multigrid level, sweep and coarsest sweeps.
        let bind = |kernel: usize, read: u32, [mg_level, mg_sweep, coarsest_sweeps]: [u32; 3]| {
            let pipeline = self.level_kernel(kernel, mg_level);
            rec.bind_pipeline(pipeline);
            rec.push_constants(
                pipeline,
                &WindPush {
                    pressure_read: read,
                    mg_level,
                    mg_sweep,
                    coarsest_sweeps,
                    ..step
                },
            );
        };
        // A kernel over `groups` workgroups.
        let dispatch = |kernel: usize, groups: u32, read: u32, mg: [u32; 3]| {
            rec.uses(&self.kernel_uses(kernel));
            bind(kernel, read, mg);
            rec.dispatch(groups);
        };
        // The colliders where they are now.
        crate::compute::colliders::record_write(
            &self.buffers.colliders,
            rec,
            &self.collider_records,
        );
        let forces = self.forces_kernel();
        rec.bind_set(forces, &self.set);
        rec.uses(&self.kernel_uses(FORCES));
        rec.bind_pipeline(forces);
        rec.push_constants(forces, &step);
        rec.dispatch(face_groups);
        match self.settings.advection {
            Advection::SemiLagrangian => dispatch(ADVECT, face_groups, 0, [0; 3]),
            Advection::Maccormack => {
                dispatch(ADVECT_PREDICT, face_groups, 0, [0; 3]);
                dispatch(ADVECT_CORRECT, face_groups, 0, [0; 3]);
            }
        }
        if self.coupled() {
            // The advection took this step's drag: clear the canopy for
            // the area the grass lays next.
            rec.fill_buffer(&self.buffers.canopy, 0);
        }
        // Among solids the projection turns the modes' flow around them
        // (`WindField::step`); without, they are added after it.
        if let (true, Some(modes)) = (self.among_solids, &modes) {
            self.record_turbulence(rec, modes, &step, true);
        }
        dispatch(DIVERGENCE, cell_groups, 0, [0; 3]);
        // A V-cycle's kernel on the workgroups of the solve buffer's
        // dispatch `arg`: zero once the residual is small enough.
        let v_cycle_dispatch = |kernel: usize, arg: usize, mg: [u32; 3]| {
            bind(kernel, 0, mg);
            let offset = (std::mem::size_of::<MgSolve>() + 16 * arg) as u64;
            rec.dispatch_indirect(&self.buffers.solve, offset, &self.kernel_uses(kernel));
        };
        self.record_pressure(&dispatch, &v_cycle_dispatch);
        dispatch(PROJECT, face_groups, 0, [0; 3]);
        if self.buried {
            dispatch(UNDER_GROUND, face_groups, 0, [0; 3]);
        }
        if let (false, Some(modes)) = (self.among_solids, &modes) {
            self.record_turbulence(rec, modes, &step, false);
        }
        self.step_recorded = rec.dispatches() - before;
    }

    /// The pressure solve: the multigrid's start (mg_start.comp), then
    /// up to `v_cycles` V-cycles (the levels from the tail down in one
    /// workgroup), each followed by its check (mg_check.comp), whose
    /// kernels run on the solve buffer's dispatches (`v_dispatch`: kernel,
    /// dispatch, [level, sweep, coarsest sweeps]), which the start and the
    /// checks switch off once the residual is small enough; or the paper's
    /// Jacobi iterations. Direct kernels through `dispatch` (kernel,
    /// workgroups, Jacobi half read, [level, sweep, coarsest sweeps]).
    fn record_pressure(
        &self,
        dispatch: &dyn Fn(usize, u32, u32, [u32; 3]),
        v_dispatch: &dyn Fn(usize, usize, [u32; 3]),
    ) {
        let multigrid = self.settings.solver == PressureSolver::Multigrid;
        let iterations = self.settings.jacobi_iterations;
        let cell_groups = self.cell_count.div_ceil(WIND_GROUP);
        if multigrid {
            // The dispatches of level l (`v_cycle_dispatches`).
            let [sweep, residual, restriction] = [0, 1, 2];
            // Level l's sweeps: fused (mg_sweep.comp), from its pressure
            // into the scratch and back, an even count; or one dispatch a
            // colour (mg_smooth.comp).
            let smooth = |l: usize, sweeps: u32| {
                for s in 0..sweeps {
                    if self.fused_sweeps {
                        v_dispatch(MG_SWEEP, 3 * l + sweep, [l as u32, s % 2, 0]);
                    } else {
                        for color in 0..2 {
                            v_dispatch(MG_SMOOTH, 3 * l + sweep, [l as u32, color, 0]);
                        }
                    }
                }
            };
            // Levels from `tail` down run in one workgroup (mg_tail.glsl).
            let tail = self.tail_level as usize;
            dispatch(MG_START, 1, 0, [0; 3]);
            for _ in 0..self.settings.v_cycles {
                for l in 0..tail {
                    smooth(l, multigrid::PRE_SMOOTH);
                    v_dispatch(MG_RESIDUAL, 3 * l + residual, [l as u32, 0, 0]);
                    v_dispatch(MG_RESTRICT, 3 * l + restriction, [l as u32, 0, 0]);
                }
                v_dispatch(
                    MG_TAIL,
                    3 * tail,
                    [tail as u32, 0, multigrid::COARSEST_SWEEPS],
                );
                for l in (0..tail).rev() {
                    v_dispatch(MG_PROLONG, 3 * l + residual, [l as u32, 0, 0]);
                    smooth(l, multigrid::POST_SMOOTH);
                }
                dispatch(MG_CHECK, 1, 0, [0; 3]);
            }
        } else {
            for i in 0..iterations {
                dispatch(JACOBI, cell_groups, i % 2, [0; 3]);
            }
        }
    }

    /// The turbulence kernel with `modes`: every face not a wall gains
    /// the field (the wind set bound); the modes finer than the grid
    /// written for the grass step.
    fn record_turbulence(
        &self,
        rec: &Recording,
        modes: &Modes,
        push: &WindPush,
        into_advected: bool,
    ) {
        rec.update_buffer(&self.buffers.modes, 0, bytemuck::cast_slice(&modes.grid));
        if !modes.subgrid.is_empty() {
            let subgrid = &self.buffers.subgrid_modes;
            rec.update_buffer(subgrid, 0, bytemuck::cast_slice(&modes.subgrid));
        }
        let pipeline = &self
            .turbulence_kernels
            .as_ref()
            .expect("modes are recorded only with turbulence, which made its kernels")
            [into_advected as usize];
        rec.uses(&self.kernel_uses(TURBULENCE));
        rec.bind_pipeline(pipeline);
        rec.push_constants(pipeline, push);
        rec.dispatch(self.face_count.div_ceil(WIND_GROUP));
    }

    /// Records the window's move by `by` whole cells (x, z) before the
    /// next step, as `WindField::shift_window` makes it: the air shifted
    /// with the grid (glsl/wind/shift.comp), the turbulence added where
    /// the faces now are; `grid` is the moved grid from then on. Over
    /// terrain the moved grid's classification (its solid cells, face
    /// kinds and multigrid tables, `Classification::of`) is written in the
    /// command buffer between the shift's two phases, the second zeroing
    /// the faces that are walls now. Refused on a grid that does not
    /// follow the camera.
    pub fn record_shift(&mut self, rec: &Recording, by: glam::IVec2) -> Result<()> {
        let Some(shift) = &self.shift else {
            return Err(Error::InvalidInput(
                "this wind grid is fixed over the field; only a [grass.cover]'s wind window follows the camera".into(),
            ));
        };
        if by == glam::IVec2::ZERO {
            return Ok(());
        }
        let uses = WIND_SHIFT_KERNEL.buffer_uses(0, &self.buffers.bound());
        let fill = self
            .settings
            .inflow
            .map_or(glam::Vec3::ZERO, |i| i.mean_velocity());
        let before = self.grid;
        let moved = before.shifted(by);
        let reclassified =
            (!self.settings.terrain.is_flat()).then(|| Classification::of(&moved, &self.settings));
        for phase in 0..2 {
            if let (1, Some(classification)) = (phase, &reclassified) {
                self.buffers.record_classification(rec, classification)?;
                self.buried = classification
                    .faces
                    .iter()
                    .flatten()
                    .any(|&k| k == FaceKind::Buried);
                self.among_solids = classification.solid.contains(&true);
            }
            rec.bind_pipeline(shift);
            rec.bind_set(shift, &self.set);
            rec.uses(&uses);
            rec.push_constants(
                shift,
                &WindShiftPush {
                    grid: grid_params(&self.grid, self.face_count),
                    shift: by.to_array(),
                    phase,
                    fill: fill.to_array(),
                    ..WindShiftPush::default()
                },
            );
            rec.dispatch(self.face_count.max(self.cell_count).div_ceil(WIND_GROUP));
        }
        self.grid = moved;
        if let Some(field) = &mut self.turbulence {
            field.move_corner(self.grid.origin - before.origin);
            let modes = Modes::of(field, self.settings.turbulence_sigma());
            // Any kernel of the wind's layout binds its set.
            rec.bind_set(self.level_kernel(FORCES, 0), &self.set);
            self.record_turbulence(rec, &modes, &self.push(0.0, 0.0), false);
        }
        Ok(())
    }

    /// The turbulence's modes at the end of a step of `dt` from now, the
    /// modes carried on by it (`WindField::add_turbulence`); None without
    /// turbulence.
    fn turbulence_records(&mut self, dt: f32) -> Option<Modes> {
        let field = self.turbulence.as_mut()?;
        let sigma = self.settings.turbulence_sigma();
        field.advance(self.settings.turbulence_convection(), sigma, dt);
        Some(Modes::of(field, sigma))
    }
}

/// The turbulence's modes as one step writes them: the grid's, and those
/// finer than the grid.
struct Modes {
    grid: Vec<TurbulenceMode>,
    subgrid: Vec<TurbulenceMode>,
}

impl Modes {
    fn of(field: &TurbulenceField, sigma: f32) -> Self {
        Self {
            grid: field.records(sigma),
            subgrid: field.subgrid_records(sigma),
        }
    }
}
