//! The wind solver on GPU compute (paper section 3.2): five kernels in
//! glsl/wind/, recorded into the frame's command buffer with a barrier
//! between each. All buffers are made once; a step allocates and uploads
//! nothing (the time and Jacobi parity travel as push constants).
//!
//! Obstacle voxelisation and the classification of every face (free, wall,
//! inflow) happen once on the CPU through `model::wind::WindField`, the same
//! code the CPU reference steps with, and are uploaded.

use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;

use crate::error::{Error, Result};
use crate::gpu::{
    Access, Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Gpu, LayoutBinding,
    MemoryLocation, Pipeline, PipelineLayout, Recording,
};
use crate::model::contact::{Collider, GpuCollider};
use crate::model::multigrid::{self, Level};
use crate::model::turbulence::{self, TurbulenceField};
use crate::model::wind::{
    Advection, Classification, FaceKind, Inflow, PressureSolver, WindField, WindGrid, WindSettings,
    WindSource,
};
use crate::shaders::{self, Spirv};

use crate::interface::{
    MgLevel, TurbulenceMode, WindGridParams, WindPush, WindShiftPush, FACE_BURIED, FACE_FREE,
    FACE_INFLOW, FACE_WALL, MG_MAX_LEVELS, MG_TAIL_FLOATS, MG_TAIL_FLOATS_LARGE, WIND_GROUP,
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
            position_radius: s.position.extend(s.radius).to_array(),
            direction_strength: dir.extend(s.strength).to_array(),
            motion: [
                s.rotation_speed,
                s.path_speed,
                s.path.len() as f32,
                s.off_after.unwrap_or(f32::INFINITY),
            ],
            gust: [s.gust.amplitude, s.gust.frequency, 0.0, 0.0],
            gust_phases: [p[0], p[1], p[2], 0.0],
            path,
        })
    }
}

/// Set 0 of the wind kernels.
pub const WIND_SET: &[LayoutBinding] = &[
    LayoutBinding::compute_storage(0),  // velocity (two copies)
    LayoutBinding::compute_storage(1),  // face kinds
    LayoutBinding::compute_storage(2),  // solid cells
    LayoutBinding::compute_storage(3),  // pressure (two copies)
    LayoutBinding::compute_storage(4),  // divergence
    LayoutBinding::compute_storage(5),  // sources
    LayoutBinding::compute_storage(6),  // multigrid face conductances
    LayoutBinding::compute_storage(7),  // multigrid coarse pressure, right-hand side
    LayoutBinding::compute_storage(8),  // multigrid level table
    LayoutBinding::compute_storage(9), // canopy: the grass's frontal area per cell (two-way coupling)
    LayoutBinding::compute_storage(10), // colliders: moving obstacles (forces kernel)
    LayoutBinding::compute_storage(11), // what the last step's turbulence added to each face
    LayoutBinding::compute_storage(12), // the turbulence's modes, written before each step
];

/// The kernels in the order a step runs them (Jacobi or the five multigrid
/// kernels solve for the pressure).
pub const WIND_KERNELS: [&Spirv; 14] = [
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
const PROJECT: usize = 11;
const UNDER_GROUND: usize = 12;
const TURBULENCE: usize = 13;

/// The tail kernel's level table in shared memory (glsl/wind/mg_tail.glsl:
/// the levels, each one's offset, two counts): its shared array's two
/// sizes leave room for it in 16 and 48 KiB.
const TAIL_TABLE_BYTES: usize = MG_MAX_LEVELS * (std::mem::size_of::<MgLevel>() + 4) + 8;
const _: () = assert!(TAIL_TABLE_BYTES + 4 * MG_TAIL_FLOATS as usize <= 16 * 1024);
const _: () = assert!(TAIL_TABLE_BYTES + 4 * MG_TAIL_FLOATS_LARGE as usize <= 48 * 1024);

/// The level table and every level's conductances, concatenated.
fn multigrid_tables(levels: &[Level]) -> (Vec<MgLevel>, Vec<f32>) {
    let mut table = Vec::new();
    let mut conductance = Vec::new();
    let mut coarse_offset = 0u32;
    for level in levels {
        let mut offsets = [0u32; 4];
        for (axis, k) in level.conductance.iter().enumerate() {
            offsets[axis] = conductance.len() as u32;
            conductance.extend_from_slice(k);
        }
        let first = table.is_empty();
        table.push(MgLevel {
            cells: level
                .cells
                .extend(if first { 0 } else { coarse_offset })
                .to_array(),
            ratio: level.ratio.extend(0).to_array(),
            conductance: offsets,
        });
        if !first {
            coarse_offset += level.cell_count() as u32;
        }
    }
    (table, conductance)
}

/// A face's kind as the kernels read it.
fn face_kind_word(kind: FaceKind) -> u32 {
    match kind {
        FaceKind::Free => FACE_FREE,
        FaceKind::Wall => FACE_WALL,
        FaceKind::Inflow => FACE_INFLOW,
        FaceKind::Buried => FACE_BURIED,
    }
}

/// The solver's buffers, made once.
struct WindBuffers {
    /// Velocity, two or three copies of every face: A (state), B
    /// (advected), and with MacCormack's advection C (its predictor).
    velocity: Buffer,
    faces: Buffer,
    solid: Buffer,
    pressure: Buffer,
    divergence: Buffer,
    sources: Buffer,
    conductance: Buffer,
    /// Pressure then right-hand side of every coarse level.
    coarse: Buffer,
    levels: Buffer,
    /// The grass's frontal area per cell in fixed point, laid by the
    /// grass step, read by the advection (src/model/canopy.rs).
    canopy: Buffer,
    /// The colliders, which push the air (`WindField::add_forces`).
    colliders: Buffer,
    /// What the last step's turbulence added to each face
    /// (`WindField::turbulence_added`): zero without turbulence.
    turbulence_added: Buffer,
    /// The turbulence's modes with their phases, written before each step
    /// (room for `turbulence::MODES`).
    modes: Buffer,
    /// The turbulence's modes finer than the grid, written with `modes`,
    /// which the grass step sums at its tips (room for
    /// `turbulence::SUBGRID_MODES`; not in the wind's set).
    subgrid_modes: Buffer,
}

impl WindBuffers {
    /// The buffers, made and filled in binding order (`WIND_SET`); the
    /// velocity as the CPU reference starts it (at rest, or at an oblique
    /// inflow's or an inflow over terrain's mean velocity: `WindField::new`),
    /// the pressure cleared to zero: the first Jacobi solve starts from
    /// zero pressure (later ones from the previous step's).
    fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        field: &WindField,
        settings: &WindSettings,
        face_count: u32,
        cell_count: u32,
    ) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let rw = storage | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
        let device_buffer = |name: &str, floats: u64| {
            Buffer::new(gpu, name, 4 * floats, rw, MemoryLocation::GpuOnly)
        };
        // The classification's buffers are written again when a window
        // over terrain moves (`record_classification`).
        let classification = storage | vk::BufferUsageFlags::TRANSFER_DST;
        let uploaded = |name: &str, bytes: &[u8]| {
            Buffer::with_data(
                gpu,
                commands,
                name,
                bytes,
                classification,
                Access::COMPUTE_READ,
            )
        };
        let coarse_cells = field.multigrid.coarse_cell_count().max(1) as u64;
        let copies = velocity_copies(settings);
        let [faces, conductance, levels] = Self::classified(gpu, commands, field)?;
        let buffers = Self {
            velocity: if field.vel.iter().flatten().all(|&v| v == 0.0) {
                device_buffer("wind velocity", copies * face_count as u64)?
            } else {
                // The air starting with an oblique inflow or over terrain
                // (`WindField::new`): every copy.
                let copy: Vec<f32> = field.vel.iter().flatten().copied().collect();
                let all = copy.repeat(copies as usize);
                Buffer::with_data(
                    gpu,
                    commands,
                    "wind velocity",
                    bytemuck::cast_slice(&all),
                    rw,
                    Access::COMPUTE_READ_WRITE,
                )?
            },
            faces,
            solid: uploaded(
                "wind solid cells",
                &u32_bytes(field.solid.iter().map(|&s| s as u32)),
            )?,
            pressure: device_buffer("wind pressure (ping, pong)", 2 * cell_count as u64)?,
            divergence: device_buffer("wind divergence", cell_count as u64)?,
            sources: Self::sources(gpu, commands, &settings.sources)?,
            conductance,
            coarse: device_buffer(
                "wind multigrid coarse levels (pressure, right-hand side)",
                2 * coarse_cells,
            )?,
            levels,
            canopy: device_buffer("wind canopy frontal area (fixed point)", cell_count as u64)?,
            colliders: super::colliders::buffer(gpu, "wind colliders")?,
            // One zero without turbulence (forces.comp reads 0 past it).
            turbulence_added: device_buffer(
                "wind turbulence added per face",
                if settings.turbulence.is_some() {
                    face_count as u64
                } else {
                    1
                },
            )?,
            modes: Buffer::new(
                gpu,
                "wind turbulence modes",
                (turbulence::MODES * std::mem::size_of::<TurbulenceMode>()) as u64,
                storage | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?,
            subgrid_modes: Buffer::new(
                gpu,
                "wind turbulence sub-grid modes",
                (turbulence::SUBGRID_MODES * std::mem::size_of::<TurbulenceMode>()) as u64,
                storage | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?,
        };
        let rec = commands.begin()?;
        if field.vel.iter().flatten().all(|&v| v == 0.0) {
            rec.fill_buffer(&buffers.velocity, 0);
        }
        rec.fill_buffer(&buffers.pressure, 0);
        rec.fill_buffer(&buffers.coarse, 0);
        rec.fill_buffer(&buffers.canopy, 0);
        rec.fill_buffer(&buffers.turbulence_added, 0);
        rec.fill_buffer(&buffers.modes, 0);
        rec.fill_buffer(&buffers.subgrid_modes, 0);
        // The next recording's first use of each waits for these writes.
        rec.submit_and_wait("clearing the wind")?;
        Ok(buffers)
    }

    /// What the faces' classification decides, uploaded: the face kinds,
    /// the multigrid's conductances and its level table.
    fn classified(gpu: &Gpu, commands: &CommandPool, field: &WindField) -> Result<[Buffer; 3]> {
        let uploaded = |name: &str, bytes: &[u8]| {
            Buffer::with_data(
                gpu,
                commands,
                name,
                bytes,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                Access::COMPUTE_READ,
            )
        };
        let kinds = field.faces.iter().flatten().map(|&k| face_kind_word(k));
        let (table, conductance) = multigrid_tables(&field.multigrid.levels);
        Ok([
            uploaded("wind face kinds", &u32_bytes(kinds))?,
            uploaded(
                "wind multigrid conductances",
                bytemuck::cast_slice(&conductance),
            )?,
            uploaded("wind multigrid levels", bytemuck::cast_slice(&table))?,
        ])
    }

    /// Writes `classification` (of a moved window over terrain) over the
    /// face kinds, solid cells and multigrid tables in the command buffer:
    /// the same grid's sizes, so the same buffers' lengths.
    fn record_classification(
        &self,
        rec: &Recording,
        classification: &Classification,
    ) -> Result<()> {
        let kinds: Vec<u32> = classification
            .faces
            .iter()
            .flatten()
            .map(|&k| face_kind_word(k))
            .collect();
        let solid: Vec<u32> = classification.solid.iter().map(|&s| s as u32).collect();
        let (table, conductance) = multigrid_tables(&classification.levels);
        let writes: [(&str, &Buffer, &[u32]); 4] = [
            ("face kinds", &self.faces, &kinds),
            ("solid cells", &self.solid, &solid),
            (
                "multigrid conductances",
                &self.conductance,
                bytemuck::cast_slice(&conductance),
            ),
            (
                "multigrid levels",
                &self.levels,
                bytemuck::cast_slice(&table),
            ),
        ];
        for (name, buffer, words) in writes {
            if 4 * words.len() as u64 != buffer.size {
                return Err(Error::InvalidInput(format!(
                    "the moved wind window's {name} take {} bytes where the buffer holds {}; the window's classification must keep its grid's sizes",
                    4 * words.len(),
                    buffer.size
                )));
            }
            rec.uses(&[BufferUse::new(buffer, Access::TRANSFER_WRITE)]);
            // vkCmdUpdateBuffer carries at most 64 KiB.
            for (n, chunk) in words.chunks(16384).enumerate() {
                rec.update_buffer(buffer, n as u64 * 65536, chunk);
            }
        }
        Ok(())
    }

    /// The sources as the kernels read them, uploaded; at least one
    /// entry (zeroed) so that the binding is never empty.
    fn sources(gpu: &Gpu, commands: &CommandPool, sources: &[WindSource]) -> Result<Buffer> {
        let mut gpu_sources = sources
            .iter()
            .map(GpuWindSource::from_source)
            .collect::<Result<Vec<_>>>()?;
        if gpu_sources.is_empty() {
            gpu_sources.push(GpuWindSource::zeroed());
        }
        Buffer::with_data(
            gpu,
            commands,
            "wind sources",
            bytemuck::cast_slice(&gpu_sources),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            Access::COMPUTE_READ,
        )
    }

    /// In the order of `WIND_SET`.
    fn bound(&self) -> [Bound<'_>; 13] {
        [
            Bound::Buffer(&self.velocity),
            Bound::Buffer(&self.faces),
            Bound::Buffer(&self.solid),
            Bound::Buffer(&self.pressure),
            Bound::Buffer(&self.divergence),
            Bound::Buffer(&self.sources),
            Bound::Buffer(&self.conductance),
            Bound::Buffer(&self.coarse),
            Bound::Buffer(&self.levels),
            Bound::Buffer(&self.canopy),
            Bound::Buffer(&self.colliders),
            Bound::Buffer(&self.turbulence_added),
            Bound::Buffer(&self.modes),
        ]
    }
}

pub struct WindPass {
    pub grid: WindGrid,
    settings: WindSettings,
    set: DescriptorSet,
    /// The kernels in `WIND_KERNELS` order, sharing one layout.
    kernels: Vec<Pipeline>,
    /// With turbulence, its kernel adding to the advected copy B, which
    /// the projection reads: among solid cells (`record_step`).
    turbulence_before_projection: Option<Pipeline>,
    layout: Arc<PipelineLayout>,
    buffers: WindBuffers,
    face_count: u32,
    cell_count: u32,
    /// Cells of each multigrid level, finest first.
    level_cells: Vec<u32>,
    /// Cells of one colour, counted as the smoother's threads are: half
    /// of each row along x, rounded up.
    level_color_cells: Vec<u32>,
    coarse_cells: u32,
    /// The finest multigrid level the tail kernel runs (mg_tail.glsl):
    /// the finest whose tail fits its shared array.
    tail_level: u32,
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
        let face_count = grid.face_count();
        let cell_count = grid.cell_count() as u64;
        // Velocity x2 or x3, face kinds, with turbulence what it added,
        // pressure x2, divergence, solid cells, canopy: 4 bytes each.
        gpu.check_fits(
            &format!(
                "the {}x{}x{} wind grid",
                grid.cells.x, grid.cells.y, grid.cells.z
            ),
            4 * ((velocity_copies(settings) + 1 + settings.turbulence.is_some() as u64)
                * face_count
                + 5 * cell_count),
        )?;
        let (face_count, cell_count) = match (u32::try_from(face_count), u32::try_from(cell_count))
        {
            (Ok(f), Ok(c)) => (f, c),
            _ => {
                return Err(Error::InvalidInput(
                    "wind grid too large for 32-bit indices".into(),
                ))
            }
        };
        let field = WindField::new(grid, settings);
        let buffers = WindBuffers::new(gpu, commands, &field, settings, face_count, cell_count)?;
        let layout: Arc<PipelineLayout> =
            PipelineLayout::new::<WindPush>(gpu, WIND_SET, vk::ShaderStageFlags::COMPUTE, "wind")?;
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
            .map(|(kernel, spirv)| match kernel {
                MG_TAIL => {
                    Pipeline::compute_specialized(gpu, &layout, tail_spirv, &[last_level as u32])
                }
                _ => Pipeline::compute(gpu, &layout, spirv),
            })
            .collect::<Result<Vec<_>>>()?;
        let turbulence_before_projection = settings
            .turbulence
            .map(|_| Pipeline::compute_specialized(gpu, &layout, WIND_KERNELS[TURBULENCE], &[1]))
            .transpose()?;
        let set = DescriptorSet::new(
            gpu,
            &layout,
            WIND_SET,
            &buffers.bound(),
            "wind descriptor set",
        )?;
        // Its set layout is the kernels' own, so their set binds to it.
        let shift = settings
            .moving_window
            .then(|| {
                let layout = PipelineLayout::new::<WindShiftPush>(
                    gpu,
                    WIND_SET,
                    vk::ShaderStageFlags::COMPUTE,
                    "wind window shift",
                )?;
                Pipeline::compute(gpu, &layout, WIND_SHIFT_KERNEL)
            })
            .transpose()?;
        Ok(Self {
            grid,
            settings: settings.clone(),
            set,
            kernels,
            turbulence_before_projection,
            layout,
            buffers,
            face_count,
            cell_count,
            level_cells: field
                .multigrid
                .levels
                .iter()
                .map(|l| l.cell_count() as u32)
                .collect(),
            level_color_cells: field
                .multigrid
                .levels
                .iter()
                .map(|l| l.cells.x.div_ceil(2) * l.cells.y * l.cells.z)
                .collect(),
            coarse_cells: field.multigrid.coarse_cell_count() as u32,
            tail_level: tail_level as u32,
            canopy_unit,
            buried: field.faces.iter().flatten().any(|&k| k == FaceKind::Buried),
            among_solids: field.solid.contains(&true),
            collider_records: super::colliders::records(&settings.colliders)?,
            turbulence: field.turbulence,
            shift,
        })
    }

    /// The finest multigrid level whose part of each V-cycle runs in the
    /// one-workgroup tail kernel (glsl/wind/mg_tail.glsl); the levels
    /// above it run kernel by kernel.
    pub fn tail_level(&self) -> u32 {
        self.tail_level
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
                WIND_SET,
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
            pressure_from_zero: multigrid as u32,
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

    /// What `kernel` reads and writes (glsl/wind/*.comp): the recording
    /// derives the barriers between the kernels, and against the grass
    /// step's reads of the velocity and writes of the canopy, from it.
    fn kernel_uses(&self, kernel: usize) -> Vec<BufferUse> {
        let b = &self.buffers;
        let (read, read_write) = (Access::COMPUTE_READ, Access::COMPUTE_READ_WRITE);
        let mut uses = vec![BufferUse::new(&b.faces, read)];
        match kernel {
            FORCES => uses.extend([
                BufferUse::new(&b.velocity, read_write),
                BufferUse::new(&b.sources, read),
                BufferUse::new(&b.colliders, read),
                BufferUse::new(&b.turbulence_added, read),
            ]),
            ADVECT | ADVECT_PREDICT | ADVECT_CORRECT => uses.extend([
                BufferUse::new(&b.velocity, read_write),
                BufferUse::new(&b.canopy, read),
            ]),
            // The solid flags: a moving window's open sides gain the modes
            // where a cell of air lies behind them.
            TURBULENCE => uses.extend([
                BufferUse::new(&b.velocity, read_write),
                BufferUse::new(&b.turbulence_added, read_write),
                BufferUse::new(&b.modes, read),
                BufferUse::new(&b.solid, read),
            ]),
            DIVERGENCE => uses.extend([
                BufferUse::new(&b.velocity, read),
                BufferUse::new(&b.solid, read),
                BufferUse::new(&b.divergence, read_write),
                BufferUse::new(&b.pressure, read_write),
            ]),
            JACOBI => uses.extend([
                BufferUse::new(&b.solid, read),
                BufferUse::new(&b.divergence, read),
                BufferUse::new(&b.pressure, read_write),
            ]),
            PROJECT => uses.extend([
                BufferUse::new(&b.velocity, read_write),
                BufferUse::new(&b.pressure, read),
            ]),
            UNDER_GROUND => uses.push(BufferUse::new(&b.velocity, read_write)),
            // The multigrid kernels (glsl/wind/multigrid.glsl): each level's
            // pressure and right-hand side, the saved residual.
            _ => uses.extend([
                BufferUse::new(&b.solid, read),
                BufferUse::new(&b.conductance, read),
                BufferUse::new(&b.levels, read),
                BufferUse::new(&b.pressure, read_write),
                BufferUse::new(&b.coarse, read_write),
                BufferUse::new(&b.divergence, read_write),
            ]),
        }
        uses
    }

    /// Records one solver step at simulation time `time`: each kernel
    /// declares what it touches (`kernel_uses`). Ends with the new velocity
    /// (copy A) written by compute; a reader declares its use. Steps the
    /// turbulence's modes on: record the steps in order.
    pub fn record_step(&mut self, rec: &Recording, time: f32, dt: f32) {
        let modes = self.turbulence_records(dt);
        let multigrid = self.settings.solver == PressureSolver::Multigrid;
        let iterations = self.settings.jacobi_iterations;
        let face_groups = self.face_count.div_ceil(WIND_GROUP);
        let cell_groups = self.cell_count.div_ceil(WIND_GROUP);
        let step = self.push(time, dt);
        // A kernel over `groups` workgroups; `read` the Jacobi half it
        // reads, `level` the multigrid level, colour and coarsest sweeps.
        let dispatch = |kernel: usize,
                        groups: u32,
                        read: u32,
                        [mg_level, mg_color, coarsest_sweeps]: [u32; 3]| {
            let pipeline = &self.kernels[kernel];
            rec.uses(&self.kernel_uses(kernel));
            rec.bind_pipeline(pipeline);
            rec.push_constants(
                pipeline,
                &WindPush {
                    pressure_read: read,
                    mg_level,
                    mg_color,
                    coarsest_sweeps,
                    ..step
                },
            );
            rec.dispatch(groups);
        };
        // The colliders where they are now.
        super::colliders::record_write(&self.buffers.colliders, rec, &self.collider_records);
        rec.bind_set(&self.kernels[FORCES], &self.set);
        dispatch(FORCES, face_groups, 0, [0; 3]);
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
            rec.uses(&[BufferUse::new(&self.buffers.canopy, Access::TRANSFER_WRITE)]);
            rec.fill_buffer(&self.buffers.canopy, 0);
        }
        // Among solids the projection turns the modes' flow around them
        // (`WindField::step`); without, they are added after it.
        if let (true, Some(modes)) = (self.among_solids, &modes) {
            self.record_turbulence(rec, modes, &step, true);
        }
        dispatch(DIVERGENCE, cell_groups, 0, [0; 3]);
        if multigrid {
            let groups = |l: usize| self.level_cells[l].div_ceil(WIND_GROUP);
            // One thread per cell of the colour being smoothed.
            let color_groups = |l: usize| self.level_color_cells[l].div_ceil(WIND_GROUP);
            let smooth = |l: usize, sweeps: u32| {
                for _ in 0..sweeps {
                    for color in 0..2 {
                        dispatch(MG_SMOOTH, color_groups(l), 0, [l as u32, color, 0]);
                    }
                }
            };
            // Levels from `tail` down run in one workgroup (mg_tail.glsl).
            let tail = self.tail_level as usize;
            for _ in 0..self.settings.v_cycles {
                for l in 0..tail {
                    smooth(l, multigrid::PRE_SMOOTH);
                    dispatch(MG_RESIDUAL, groups(l), 0, [l as u32, 0, 0]);
                    dispatch(MG_RESTRICT, groups(l + 1), 0, [l as u32, 0, 0]);
                }
                dispatch(MG_TAIL, 1, 0, [tail as u32, 0, multigrid::COARSEST_SWEEPS]);
                for l in (0..tail).rev() {
                    dispatch(MG_PROLONG, groups(l), 0, [l as u32, 0, 0]);
                    smooth(l, multigrid::POST_SMOOTH);
                }
            }
        } else {
            for i in 0..iterations {
                dispatch(JACOBI, cell_groups, i % 2, [0; 3]);
            }
        }
        dispatch(PROJECT, face_groups, 0, [0; 3]);
        if self.buried {
            dispatch(UNDER_GROUND, face_groups, 0, [0; 3]);
        }
        if let (false, Some(modes)) = (self.among_solids, &modes) {
            self.record_turbulence(rec, modes, &step, false);
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
        rec.uses(&[BufferUse::new(&self.buffers.modes, Access::TRANSFER_WRITE)]);
        rec.update_buffer(&self.buffers.modes, 0, bytemuck::cast_slice(&modes.grid));
        if !modes.subgrid.is_empty() {
            let subgrid = &self.buffers.subgrid_modes;
            rec.uses(&[BufferUse::new(subgrid, Access::TRANSFER_WRITE)]);
            rec.update_buffer(subgrid, 0, bytemuck::cast_slice(&modes.subgrid));
        }
        // Modes are recorded only with turbulence, which made both.
        let pipeline = match (&self.turbulence_before_projection, into_advected) {
            (Some(before), true) => before,
            _ => &self.kernels[TURBULENCE],
        };
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
        let b = &self.buffers;
        let (read, read_write) = (Access::COMPUTE_READ, Access::COMPUTE_READ_WRITE);
        let uses = [
            BufferUse::new(&b.velocity, read_write),
            BufferUse::new(&b.faces, read),
            BufferUse::new(&b.pressure, read_write),
            BufferUse::new(&b.divergence, read_write),
            BufferUse::new(&b.canopy, read_write),
            BufferUse::new(&b.turbulence_added, read),
        ];
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
            rec.bind_set(&self.kernels[TURBULENCE], &self.set);
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
