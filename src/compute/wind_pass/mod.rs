//! The wind solver on GPU compute (paper section 3.2): five kernels in
//! glsl/wind/, recorded into the frame's command buffer with a barrier
//! between each. All buffers are made once; a step allocates and uploads
//! nothing (the time and Jacobi parity travel as push constants).
//!
//! Obstacle voxelisation and the classification of every face (free, wall,
//! inflow) happen once on the CPU through `model::wind::WindField`, the same
//! code the CPU reference steps with, and are uploaded.
//!
//! This file holds the pass, its kernels and the drive it is given; its
//! children, which use only this file and the layers below: `buffers.rs`
//! (the buffers and their set), `record.rs` (a step and a shift recorded).

use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;

use crate::error::{Error, Result};
use crate::gpu::{
    Access, Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Dispatches, Gpu, LayoutBinding,
    MemoryLocation, Pipeline, PipelineLayout, Recording,
};
use crate::model::contact::{Collider, GpuCollider};
use crate::model::multigrid::{self, Level, SolveCounts};
use crate::model::turbulence::{self, TurbulenceField};
use crate::model::wind::{
    Advection, Classification, FaceKind, Inflow, PressureSolver, Sweep, WindField, WindGrid,
    WindSettings, WindSource,
};
use crate::shaders::{self, Spirv};

mod buffers;
mod record;

use buffers::WindBuffers;

use crate::interface::{
    MgLevel, MgSolve, TurbulenceMode, WindGridParams, WindPush, WindShiftPush, FACE_BURIED,
    FACE_FREE, FACE_INFLOW, FACE_WALL, MG_MAX_LEVELS, MG_SWEEP_TILE_X, MG_SWEEP_TILE_Y,
    MG_SWEEP_TILE_Z, MG_TAIL_FLOATS, MG_TAIL_FLOATS_LARGE, WIND_GROUP,
};
/// Waypoints a source's path may have on the GPU.
pub use crate::model::wind::MAX_PATH_POINTS;

/// One wind source as the kernels read it (src/interface/defs.rs).
pub use crate::interface::GpuWindSource;

impl GpuWindSource {
    pub fn from_source(s: &WindSource) -> Result<Self> {
        if s.path.len() > MAX_PATH_POINTS {
            return Err(Error::InvalidInput(format!(
                "a wind source path has {} points, use at most {MAX_PATH_POINTS}",
                s.path.len()
            )));
        }
        let mut path = [[0.0; 4]; MAX_PATH_POINTS];
        for (dst, p) in path.iter_mut().zip(&s.path) {
            *dst = p.extend(0.0).to_array();
        }
        let dir = s.direction.try_normalize().unwrap_or(glam::Vec3::X);
        let p = s.gust.phases();
        Ok(Self {
            position: s.position.to_array(),
            radius: s.radius,
            direction: dir.to_array(),
            strength: s.strength,
            gust_phases: [p[0], p[1], p[2]],
            gust_amplitude: s.gust.amplitude,
            gust_frequency: s.gust.frequency,
            rotation_speed: s.rotation_speed,
            path_speed: s.path_speed,
            off_after: s.off_after.unwrap_or(f32::INFINITY),
            path_points: s.path.len() as u32,
            path,
            ..Self::default()
        })
    }
}

/// Set 0 of the wind kernels, as they use it (build.rs's reflection of
/// glsl/wind/*.comp): what binding b holds is `WindBuffers::bound`'s b-th.
pub fn wind_set() -> Vec<LayoutBinding> {
    let mut kernels: Vec<&Spirv> = WIND_KERNELS.to_vec();
    kernels.extend(WIND_KERNEL_VARIANTS);
    kernels.push(WIND_SHIFT_KERNEL);
    crate::gpu::kernels_set(&kernels, 0)
}

/// The kernels in the order a step runs them (Jacobi or the multigrid
/// kernels solve for the pressure; the multigrid's start and check last).
pub const WIND_KERNELS: [&Spirv; 17] = [
    &shaders::WIND_FORCES_COMP,
    &shaders::WIND_ADVECT_COMP,
    &shaders::WIND_ADVECT_PREDICT_COMP,
    &shaders::WIND_ADVECT_CORRECT_COMP,
    &shaders::WIND_DIVERGENCE_COMP,
    &shaders::WIND_JACOBI_COMP,
    &shaders::WIND_MG_SMOOTH_COMP,
    &shaders::WIND_MG_RESIDUAL_COMP,
    &shaders::WIND_MG_RESTRICT_COMP,
    &shaders::WIND_MG_TAIL_COMP,
    &shaders::WIND_MG_PROLONG_COMP,
    &shaders::WIND_PROJECT_COMP,
    &shaders::WIND_UNDER_GROUND_COMP,
    &shaders::WIND_TURBULENCE_COMP,
    &shaders::WIND_MG_START_COMP,
    &shaders::WIND_MG_CHECK_COMP,
    &shaders::WIND_MG_SWEEP_COMP,
];
const FORCES: usize = 0;
const ADVECT: usize = 1;
const ADVECT_PREDICT: usize = 2;
const ADVECT_CORRECT: usize = 3;
const DIVERGENCE: usize = 4;
const JACOBI: usize = 5;
/// The wind window's shift (`WindPass::record_shift`): the wind kernels'
/// set, its own push constants (`WindShiftPush`).
pub const WIND_SHIFT_KERNEL: &Spirv = &shaders::WIND_SHIFT_COMP;
/// Kernels that stand in for one of `WIND_KERNELS` on some devices, on the
/// same layout and push constants: the tail with its 48 KiB shared array.
pub const WIND_KERNEL_VARIANTS: [&Spirv; 1] = [&shaders::WIND_MG_TAIL_LARGE_COMP];
const MG_SMOOTH: usize = 6;
const MG_RESIDUAL: usize = 7;
const MG_RESTRICT: usize = 8;
const MG_TAIL: usize = 9;
const MG_PROLONG: usize = 10;
/// The V-cycle's kernels that run on one level at a time, each made twice:
/// for level 0 and for the coarse levels (multigrid.glsl's MG_ANY_LEVEL).
const LEVEL_KERNELS: [usize; 5] = [MG_SMOOTH, MG_RESIDUAL, MG_RESTRICT, MG_PROLONG, MG_SWEEP];
const PROJECT: usize = 11;
const UNDER_GROUND: usize = 12;
const TURBULENCE: usize = 13;
const MG_START: usize = 14;
const MG_CHECK: usize = 15;
/// Both colours of a sweep in one dispatch (`Sweep::Fused`); MG_SMOOTH
/// runs one.
const MG_SWEEP: usize = 16;

pub struct WindPass {
    pub grid: WindGrid,
    settings: WindSettings,
    set: DescriptorSet,
    /// The kernels in `WIND_KERNELS` order, sharing one layout, each made
    /// where this pass runs it (`runs_kernel`); those of `LEVEL_KERNELS`
    /// made for the coarse levels (`level_kernel`).
    kernels: Vec<Option<Pipeline>>,
    /// `LEVEL_KERNELS` made for level 0, where the pass runs them.
    finest_kernels: [Option<Pipeline>; 5],
    /// With turbulence, its kernel specialised to the axes the field's
    /// modes are mirrored across (which the pass's life does not change),
    /// adding to the state A and to the advected copy B, which the
    /// projection reads: among solid cells (`record_step`).
    turbulence_kernels: Option<[Pipeline; 2]>,
    /// The forces kernel specialised to a step with sources only (0),
    /// colliders only (1) or neither (2); `kernels[FORCES]` has both
    /// (`forces_kernel`). The viewer adds and removes colliders and
    /// sources between steps, so every variant is made once, here.
    forces_without: [Pipeline; 3],
    layout: Arc<PipelineLayout>,
    buffers: WindBuffers,
    face_count: u32,
    cell_count: u32,
    coarse_cells: u32,
    /// The finest multigrid level the tail kernel runs (mg_tail.glsl):
    /// the finest whose tail fits its shared array.
    tail_level: u32,
    /// Whether a sweep's two colours run in one dispatch (`Sweep`).
    fused_sweeps: bool,
    /// m^2 per count of the canopy buffer (`model::canopy::unit` of the
    /// grass coupled to this wind; 0 with no grass).
    canopy_unit: f32,
    /// Whether any face lies between two cells under the ground (then
    /// each step ends with glsl/wind/under_ground.comp).
    buried: bool,
    /// Whether any cell is solid (the ground, an obstacle): then the
    /// turbulence is added before the projection (`record_step`).
    among_solids: bool,
    /// The colliders as forces.comp reads them, written before each step.
    collider_records: Vec<GpuCollider>,
    /// The turbulence's modes and how far they have gone (None: no
    /// turbulence), stepped as the CPU reference steps them.
    turbulence: Option<TurbulenceField>,
    /// The window's shift kernel, where the grid follows the camera
    /// (`WindSettings::moving_window`).
    shift: Option<Pipeline>,
    /// The dispatches the last `record_step` recorded.
    step_recorded: Dispatches,
}

/// The wind as the grass step sees it: the velocity it samples and, with
/// two-way coupling, the buffer it lays its frontal area into and that
/// buffer's unit (m^2 per count). Owned by the wind solver, or a test.
pub struct WindInput<'a> {
    pub grid: WindGrid,
    pub velocity: &'a Buffer,
    /// None: one-way coupling, the grass lays nothing.
    pub canopy: Option<(&'a Buffer, f32)>,
    /// The turbulence's modes finer than the grid, which the tips sum, and
    /// how many (`WindPass::subgrid_records`); None: none.
    pub subgrid: Option<(&'a Buffer, u32)>,
}

fn u32_bytes(values: impl Iterator<Item = u32>) -> Vec<u8> {
    values.flat_map(u32::to_le_bytes).collect()
}

/// The grid's face and cell counts, refused where the grid's buffers
/// would not fit the GPU's memory or its indices 32 bits.
fn fitted_counts(gpu: &Gpu, grid: &WindGrid, settings: &WindSettings) -> Result<(u32, u32)> {
    let face_count = grid.face_count();
    let cell_count = grid.cell_count() as u64;
    // Velocity x2 or x3, face kinds, with turbulence what it added,
    // pressure x3, divergence, solid cells, canopy: 4 bytes each.
    gpu.check_fits(
        &format!(
            "the {}x{}x{} wind grid",
            grid.cells.x, grid.cells.y, grid.cells.z
        ),
        4 * ((velocity_copies(settings) + 1 + settings.turbulence.is_some() as u64) * face_count
            + 6 * cell_count),
    )?;
    match (u32::try_from(face_count), u32::try_from(cell_count)) {
        (Ok(f), Ok(c)) => Ok((f, c)),
        _ => Err(Error::InvalidInput(
            "wind grid too large for 32-bit indices".into(),
        )),
    }
}

/// `WindPass::kernels`, `WindPass::finest_kernels` and the tail level.
type WindKernels = (Vec<Option<Pipeline>>, [Option<Pipeline>; 5], usize);

/// The wind's kernels (`LEVEL_KERNELS` for the coarse levels), those of
/// `LEVEL_KERNELS` for level 0, and the finest multigrid level the tail
/// kernel runs from. The tail kernel is the variant with the larger shared
/// array where the device offers it, specialised to this grid's coarsest
/// level.
fn wind_kernels(
    gpu: &Gpu,
    layout: &Arc<PipelineLayout>,
    field: &WindField,
    runs: impl Fn(usize) -> bool,
) -> Result<WindKernels> {
    // The tail kernel: the variant with the larger shared array where
    // the device offers it, from the finest level that fits it, and
    // specialised to this grid's coarsest level.
    let large = gpu.limits().max_compute_shared_memory_size as usize >= 48 * 1024;
    let (tail_spirv, tail_floats) = if large {
        (WIND_KERNEL_VARIANTS[0], MG_TAIL_FLOATS_LARGE)
    } else {
        (WIND_KERNELS[MG_TAIL], MG_TAIL_FLOATS)
    };
    let last_level = field.multigrid.levels.len() - 1;
    // The coarsest level (at most `MAX_COARSEST_CELLS` cells) always
    // fits: this cannot fail on any grid `Multigrid::new` makes.
    let tail_level = field
        .multigrid
        .tail_level(tail_floats as usize)
        .ok_or_else(|| {
            Error::InvalidInput(format!(
                "the multigrid's coarsest level needs {} floats, more than the tail \
                 kernel's {tail_floats}; set wind.solver = \"jacobi\"",
                field.multigrid.tail_footprint(last_level)
            ))
        })?;
    let kernels = WIND_KERNELS
        .iter()
        .enumerate()
        .map(|(kernel, spirv)| {
            runs(kernel)
                .then(|| match kernel {
                    MG_TAIL => Pipeline::compute_specialized(
                        gpu,
                        layout,
                        tail_spirv,
                        &[(0, last_level as u32)],
                    ),
                    // MG_ANY_LEVEL 0, MG_ON_FINEST 0: the coarse levels.
                    k if LEVEL_KERNELS.contains(&k) => {
                        Pipeline::compute_specialized(gpu, layout, spirv, &[(8, 0), (9, 0)])
                    }
                    _ => Pipeline::compute(gpu, layout, spirv),
                })
                .transpose()
        })
        .collect::<Result<Vec<_>>>()?;
    let [a, b, c, d, e] = LEVEL_KERNELS.map(|k| {
        // MG_ANY_LEVEL 1, MG_ON_FINEST 1: level 0 (and the next one read).
        runs(k)
            .then(|| Pipeline::compute_specialized(gpu, layout, WIND_KERNELS[k], &[(8, 1), (9, 1)]))
            .transpose()
    });
    Ok((kernels, [a?, b?, c?, d?, e?], tail_level))
}

/// Whether a pass with `settings` (its sweeps `fused`) runs `kernel` of
/// `WIND_KERNELS`: only those are made (on lavapipe, making pipelines was
/// about half of a small bench run's time). They do not change
/// over the pass's life: its solver, advection and sweeps are fixed.
fn runs_kernel(kernel: usize, settings: &WindSettings, fused: bool) -> bool {
    let multigrid = settings.solver == PressureSolver::Multigrid;
    match kernel {
        ADVECT => settings.advection == Advection::SemiLagrangian,
        ADVECT_PREDICT | ADVECT_CORRECT => settings.advection == Advection::Maccormack,
        JACOBI => !multigrid,
        MG_SMOOTH => multigrid && !fused,
        MG_SWEEP => multigrid && fused,
        MG_RESIDUAL | MG_RESTRICT | MG_TAIL | MG_PROLONG | MG_START | MG_CHECK => multigrid,
        // The turbulence runs its kernels specialised to the field's
        // mirrored axes (`turbulence_kernels`), never the general one.
        TURBULENCE => false,
        _ => true,
    }
}

/// The workgroup counts of a V-cycle's dispatches as the solve buffer
/// holds them (`MgSolve`): for each level above the tail its smoothing
/// (`fused`: one workgroup a tile, `sweep_tiles`; else one thread per cell
/// of a colour), its residual and its restriction (the coarser level's
/// cells) at 3 l, 3 l + 1 and 3 l + 2; the tail's one workgroup last. A
/// level's prolongation runs over its cells, as its residual.
fn v_cycle_dispatches(levels: &[Level], tail: usize, fused: bool) -> Vec<[u32; 4]> {
    let groups = |l: usize| (levels[l].cell_count() as u32).div_ceil(WIND_GROUP);
    let smoothing = |l: usize| {
        let n = levels[l].cells;
        if fused {
            sweep_tiles(n)
        } else {
            (n.x.div_ceil(2) * n.y * n.z).div_ceil(WIND_GROUP)
        }
    };
    let mut args: Vec<[u32; 4]> = (0..tail)
        .flat_map(|l| [smoothing(l), groups(l), groups(l + 1)])
        .map(|x| [x, 1, 1, 0])
        .collect();
    args.push([1, 1, 1, 0]);
    args
}

// mg_sweep.comp's sweeps go from a level's pressure into the scratch and
// back: a pair ends where the level's pressure is read next.
const _: () =
    assert!(crate::interface::MG_PRE_SMOOTH % 2 == 0 && crate::interface::MG_POST_SMOOTH % 2 == 0);
// Its shared array holds the red cells of a tile and one cell around it.
const _: () = assert!(
    (MG_SWEEP_TILE_X + 3) / 2 * (MG_SWEEP_TILE_Y + 2) * (MG_SWEEP_TILE_Z + 2)
        <= crate::interface::MG_SWEEP_FLOATS
);

/// The tiles glsl/wind/mg_sweep.comp sweeps a level of `cells` in, one
/// workgroup each: `MG_SWEEP_TILE_*` cells, fewer along an axis the level
/// is shorter than (the kernel works the same tiles out).
fn sweep_tiles(cells: glam::UVec3) -> u32 {
    let tile = cells.min(glam::UVec3::new(
        MG_SWEEP_TILE_X,
        MG_SWEEP_TILE_Y,
        MG_SWEEP_TILE_Z,
    ));
    let tiles = (cells + tile - 1) / tile;
    tiles.x * tiles.y * tiles.z
}

/// The kernel that shifts the wind window under the camera; its set
/// layout is the kernels' own, so their set binds to it.
fn shift_kernel(gpu: &Gpu) -> Result<Pipeline> {
    let layout = PipelineLayout::new::<WindShiftPush>(
        gpu,
        &wind_set(),
        vk::ShaderStageFlags::COMPUTE,
        "wind window shift",
    )?;
    Pipeline::compute(gpu, &layout, WIND_SHIFT_KERNEL)
}

/// The forces kernel without what a step may lack, in `forces_without`'s
/// order: without colliders, without sources, without either.
fn forces_kernels(gpu: &Gpu, layout: &Arc<PipelineLayout>) -> Result<[Pipeline; 3]> {
    // WITH_SOURCES, WITH_COLLIDERS.
    let [a, b, c] = [[1, 0], [0, 1], [0, 0]].map(|[sources, colliders]| {
        let constants = [(0, sources), (1, colliders)];
        Pipeline::compute_specialized(gpu, layout, WIND_KERNELS[FORCES], &constants)
    });
    Ok([a?, b?, c?])
}

/// The turbulence kernel specialised to the axes the field's modes are
/// mirrored across, writing in place and into the copy; none without
/// turbulence.
fn turbulence_kernels(
    gpu: &Gpu,
    layout: &Arc<PipelineLayout>,
    field: &WindField,
) -> Result<Option<[Pipeline; 2]>> {
    field
        .turbulence
        .as_ref()
        .map(|t| {
            // INTO_COPY; FROM_MODES 0 and MIRRORED the field's.
            let kernel = |into_copy: u32| {
                Pipeline::compute_specialized(
                    gpu,
                    layout,
                    WIND_KERNELS[TURBULENCE],
                    &[(0, into_copy), (1, 0), (2, t.mirrored())],
                )
            };
            Ok::<_, Error>([kernel(0)?, kernel(1)?])
        })
        .transpose()
}

impl WindPass {
    /// The solver for `settings` on `grid`. `canopy_unit` is the m^2 per
    /// count of the frontal area the coupled grass lays
    /// (`model::canopy::unit` of its blades; 0 with no grass).
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        grid: WindGrid,
        settings: &WindSettings,
        canopy_unit: f32,
    ) -> Result<Self> {
        let (face_count, cell_count) = fitted_counts(gpu, &grid, settings)?;
        let field = WindField::new(grid, settings);
        let layout: Arc<PipelineLayout> = PipelineLayout::new::<WindPush>(
            gpu,
            &wind_set(),
            vk::ShaderStageFlags::COMPUTE,
            "wind",
        )?;
        let fused_sweeps = match settings.sweep {
            Sweep::Auto => !gpu.info().is_cpu(),
            Sweep::Fused => true,
            Sweep::Split => false,
        };
        let (kernels, finest_kernels, tail_level) = wind_kernels(gpu, &layout, &field, |k| {
            runs_kernel(k, settings, fused_sweeps)
        })?;
        let mg_dispatches = v_cycle_dispatches(&field.multigrid.levels, tail_level, fused_sweeps);
        let buffers = WindBuffers::new(
            gpu,
            commands,
            &field,
            settings,
            [face_count, cell_count],
            &mg_dispatches,
        )?;
        let forces_without = forces_kernels(gpu, &layout)?;
        let turbulence_kernels = turbulence_kernels(gpu, &layout, &field)?;
        let set = DescriptorSet::new(
            gpu,
            &layout,
            &wind_set(),
            &buffers.bound(),
            "wind descriptor set",
        )?;
        let shift = settings
            .moving_window
            .then(|| shift_kernel(gpu))
            .transpose()?;
        Ok(Self {
            grid,
            settings: settings.clone(),
            set,
            kernels,
            finest_kernels,
            turbulence_kernels,
            forces_without,
            layout,
            buffers,
            face_count,
            cell_count,
            coarse_cells: field.multigrid.coarse_cell_count() as u32,
            tail_level: tail_level as u32,
            fused_sweeps,
            canopy_unit,
            buried: field.faces.iter().flatten().any(|&k| k == FaceKind::Buried),
            among_solids: field.solid.contains(&true),
            collider_records: super::colliders::records(&settings.colliders)?,
            turbulence: field.turbulence,
            shift,
            step_recorded: Dispatches::default(),
        })
    }

    /// The finest multigrid level whose part of each V-cycle runs in the
    /// one-workgroup tail kernel (glsl/wind/mg_tail.glsl); the levels
    /// above it run kernel by kernel.
    pub fn tail_level(&self) -> u32 {
        self.tail_level
    }

    /// How the multigrid's sweeps run on this device: fused or split
    /// (`Sweep`, "auto" resolved).
    pub fn sweep(&self) -> Sweep {
        if self.fused_sweeps {
            Sweep::Fused
        } else {
            Sweep::Split
        }
    }

    /// Whether the grid is a window that follows the camera
    /// (`record_shift`).
    pub fn follows_camera(&self) -> bool {
        self.shift.is_some()
    }

    /// What drives the wind now: the scene's settings, as `set_drive`
    /// last changed them.
    pub fn settings(&self) -> &WindSettings {
        &self.settings
    }

    /// Changes what drives the wind from the next step on (the viewer's
    /// wind keys and dropped gusts): the inflow (its speed and heading)
    /// and the sources. An inflow that enters or leaves by other sides
    /// than before reclassifies the faces (`WindField::classify_faces`)
    /// and uploads them with their multigrid tables; the air keeps its
    /// velocity. Uploads and waits: call between submissions.
    pub fn set_drive(
        &mut self,
        gpu: &Gpu,
        commands: &CommandPool,
        inflow: Option<Inflow>,
        sources: &[WindSource],
    ) -> Result<()> {
        if let Some(i) = &inflow {
            if !(i.speed.is_finite() && i.heading.is_finite()) {
                return Err(Error::InvalidInput(format!(
                    "an inflow of {} m/s towards {} degrees is not allowed, use finite numbers",
                    i.speed, i.heading
                )));
            }
        }
        let mut replaced = Vec::new();
        let sides = |i: Option<&Inflow>| {
            i.map(|i| [(0, 0), (0, 1), (2, 0), (2, 1)].map(|(a, e)| i.side(a, e)))
        };
        if sides(inflow.as_ref()) != sides(self.settings.inflow.as_ref()) {
            let next = WindSettings {
                inflow,
                ..self.settings.clone()
            };
            let field = WindField::new(self.grid, &next);
            let [faces, conductance, levels] = WindBuffers::classified(gpu, commands, &field)?;
            replaced.push(std::mem::replace(&mut self.buffers.faces, faces));
            replaced.push(std::mem::replace(
                &mut self.buffers.conductance,
                conductance,
            ));
            replaced.push(std::mem::replace(&mut self.buffers.levels, levels));
        }
        self.settings.inflow = inflow;
        if sources != self.settings.sources.as_slice() {
            let buffer = WindBuffers::sources(gpu, commands, sources)?;
            replaced.push(std::mem::replace(&mut self.buffers.sources, buffer));
            self.settings.sources = sources.to_vec();
        }
        if !replaced.is_empty() {
            // The new set replaces (and drops) the old one before the old
            // buffers it named go; no submission is in flight.
            self.set = DescriptorSet::new(
                gpu,
                &self.layout,
                &wind_set(),
                &self.buffers.bound(),
                "wind descriptor set",
            )?;
            drop(replaced);
        }
        Ok(())
    }

    /// The colliders pushing the air from the next recorded step on (the
    /// viewer's ball): written in the command buffer, no upload.
    pub fn set_colliders(&mut self, colliders: &[Collider]) -> Result<()> {
        self.collider_records = super::colliders::records(colliders)?;
        self.settings.colliders = colliders.to_vec();
        Ok(())
    }

    /// Whether the grass slows this wind (two-way coupling with grass).
    fn coupled(&self) -> bool {
        self.settings.effective_canopy_drag() > 0.0 && self.canopy_unit > 0.0
    }

    /// What the grass step binds: the velocity, the canopy buffer when
    /// the coupling is two-way, and the turbulence's modes finer than the
    /// grid where there are any.
    pub fn grass_input(&self) -> WindInput<'_> {
        let subgrid = self
            .turbulence
            .as_ref()
            .map_or(0, |field| field.subgrid_count() as u32);
        WindInput {
            grid: self.grid,
            velocity: &self.buffers.velocity,
            canopy: self
                .coupled()
                .then_some((&self.buffers.canopy, self.canopy_unit)),
            subgrid: (subgrid > 0).then_some((&self.buffers.subgrid_modes, subgrid)),
        }
    }

    /// The turbulence's modes finer than the grid as the last recorded
    /// step leaves them (`TurbulenceField::subgrid_records`): what the
    /// grass step sums at its tips (`WindField::felt` on the CPU); empty
    /// without.
    pub fn subgrid_records(&self) -> Vec<TurbulenceMode> {
        self.turbulence.as_ref().map_or(Vec::new(), |field| {
            field.subgrid_records(self.settings.turbulence_sigma())
        })
    }

    /// The frontal area per cell the grass laid last step, in counts of
    /// `canopy_unit` m^2 (for tests and pictures).
    pub fn read_canopy(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<u32>> {
        self.buffers
            .canopy
            .read_back(gpu, commands, self.cell_count as usize)
    }

    /// Copies the velocity (copy A: x, y, z components) back to the host:
    /// for tests, pictures and statistics, not per frame.
    pub fn read_velocity(&self, gpu: &Gpu, commands: &CommandPool) -> Result<[Vec<f32>; 3]> {
        let all: Vec<f32> =
            self.buffers
                .velocity
                .read_back(gpu, commands, self.face_count as usize)?;
        let mut split = [Vec::new(), Vec::new(), Vec::new()];
        let mut start = 0;
        for (axis, dst) in split.iter_mut().enumerate() {
            let d = self.grid.face_dims(axis);
            let n = (d.x * d.y * d.z) as usize;
            *dst = all[start..start + n].to_vec();
            start += n;
        }
        Ok(split)
    }

    /// What the multigrid's solves did (`MgSolve`): the last step's
    /// V-cycles, start and share of the divergence left, and the steps
    /// before it by their V-cycles.
    pub fn read_solve(&self, gpu: &Gpu, commands: &CommandPool) -> Result<MgSolve> {
        let head: Vec<MgSolve> = self.buffers.solve.read_back(gpu, commands, 1)?;
        Ok(head[0])
    }

    /// The multigrid's V-cycles per step over the steps recorded so far,
    /// read back (`MgSolve`'s histogram and the last step's count), and
    /// the dispatches a step records and those that run workgroups; None
    /// with the Jacobi solver or before a step.
    pub fn read_solve_counts(
        &self,
        gpu: &Gpu,
        commands: &CommandPool,
    ) -> Result<Option<SolveCounts>> {
        if self.settings.solver != PressureSolver::Multigrid {
            return Ok(None);
        }
        let solve = self.read_solve(gpu, commands)?;
        if solve.steps == 0 {
            return Ok(None);
        }
        // Steps by their V-cycles: the histogram of those before the
        // last, and the last.
        let mut by_cycles = solve.histogram;
        let last = (solve.v_cycles as usize).min(by_cycles.len() - 1);
        by_cycles[last] += 1;
        let steps: u32 = by_cycles.iter().sum();
        // The V-cycles of the step at index steps / 2 in sorted order.
        let mut below = 0;
        let median = by_cycles
            .iter()
            .position(|&n| {
                below += n;
                below > steps / 2
            })
            .unwrap_or(0) as u32;
        let most = by_cycles.iter().rposition(|&n| n > 0).unwrap_or(0) as u32;
        let total: u32 = (0..).zip(by_cycles).map(|(cycles, n)| cycles * n).sum();
        Ok(Some(SolveCounts {
            steps: solve.steps,
            v_cycles_median: median,
            v_cycles_most: most,
            v_cycles_mean: total as f32 / steps as f32,
            dispatches_median: self.step_dispatches(Some(median)),
            dispatches_recorded: self.step_dispatches(None),
        }))
    }

    /// The dispatches of a step that run workgroups when its solve runs
    /// `v_cycles` V-cycles (None: every one recorded, `wind.v_cycles`;
    /// a V-cycle switched off still records its dispatches, on zero
    /// workgroups), as the last `record_step` counted them: its direct
    /// dispatches (the checks after each V-cycle among them) and its
    /// V-cycles' indirect ones. 0 before a step is recorded.
    pub fn step_dispatches(&self, v_cycles: Option<u32>) -> u32 {
        let recorded = self.step_recorded;
        let cap = self.settings.v_cycles.max(1);
        let per_v_cycle = recorded.indirect / cap;
        recorded.direct + v_cycles.unwrap_or(cap).min(cap) * per_v_cycle
    }

    /// The divergence of the last step's advected field, before projection.
    pub fn read_divergence(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<f32>> {
        self.buffers
            .divergence
            .read_back(gpu, commands, self.cell_count as usize)
    }

    /// The velocity buffer: copy A (the state between steps) starts at 0,
    /// in the layout of glsl/common/wind_grid.glsl. The grass samples it.
    pub fn velocity(&self) -> &Buffer {
        &self.buffers.velocity
    }
}

/// Copies of the velocity the advection needs: A and B, and C for
/// MacCormack's predictor (only then, so that the paper's advection keeps
/// the binding within a small maxStorageBufferRange).
fn velocity_copies(settings: &WindSettings) -> u64 {
    match settings.advection {
        Advection::SemiLagrangian => 2,
        Advection::Maccormack => 3,
    }
}

/// The wind grid as the kernels read it (`WindGridParams`), with `faces`
/// faces in one velocity copy.
pub fn grid_params(grid: &WindGrid, faces: u32) -> WindGridParams {
    WindGridParams {
        cells: grid.cells.to_array(),
        faces,
        origin: grid.origin.to_array(),
        cell_size: grid.cell.to_array(),
        ..WindGridParams::default()
    }
}
