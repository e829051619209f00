//! The wind solver's buffers: the velocity copies, pressure, divergence,
//! the faces' classification, the multigrid tables and the sources, made
//! once per scene, and the set they are bound in.

use super::*;

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
        let mut offsets = [0u32; 3];
        for (axis, k) in level.conductance.iter().enumerate() {
            offsets[axis] = conductance.len() as u32;
            conductance.extend_from_slice(k);
        }
        let first = table.is_empty();
        table.push(MgLevel {
            cells: level.cells.to_array(),
            coarse_offset: if first { 0 } else { coarse_offset },
            ratio: level.ratio.to_array(),
            conductance: offsets,
            ..MgLevel::default()
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
pub(super) struct WindBuffers {
    /// Velocity, two or three copies of every face: A (state), B
    /// (advected), and with MacCormack's advection C (its predictor).
    pub(super) velocity: Buffer,
    pub(super) faces: Buffer,
    pub(super) solid: Buffer,
    pub(super) pressure: Buffer,
    pub(super) divergence: Buffer,
    pub(super) sources: Buffer,
    pub(super) conductance: Buffer,
    /// Pressure then right-hand side of every coarse level.
    pub(super) coarse: Buffer,
    pub(super) levels: Buffer,
    /// The grass's frontal area per cell in fixed point, laid by the
    /// grass step, read by the advection (src/model/canopy.rs).
    pub(super) canopy: Buffer,
    /// The colliders, which push the air (`WindField::add_forces`).
    pub(super) colliders: Buffer,
    /// What the last step's turbulence added to each face
    /// (`WindField::turbulence_added`): zero without turbulence.
    pub(super) turbulence_added: Buffer,
    /// The turbulence's modes with their phases, written before each step
    /// (room for `turbulence::MODES`).
    pub(super) modes: Buffer,
    /// The multigrid's solve: its head (`MgSolve`) and the V-cycle's
    /// indirect dispatches, live then as made (glsl/wind/mg_solve.glsl).
    pub(super) solve: Buffer,
    /// The turbulence's modes finer than the grid, written with `modes`,
    /// which the grass step sums at its tips (room for
    /// `turbulence::SUBGRID_MODES`; not in the wind's set).
    pub(super) subgrid_modes: Buffer,
}

impl WindBuffers {
    /// The buffers, made and filled in binding order (`bound`); the
    /// velocity as the CPU reference starts it (at rest, or at an oblique
    /// inflow's or an inflow over terrain's mean velocity: `WindField::new`),
    /// the pressure cleared to zero: the first Jacobi solve starts from
    /// zero pressure (later ones from the previous step's).
    pub(super) fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        field: &WindField,
        settings: &WindSettings,
        [face_count, cell_count]: [u32; 2],
        v_cycle_dispatches: &[[u32; 4]],
    ) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let device_buffer = |name: &str, floats: u64| {
            Buffer::new(gpu, name, 4 * floats, READ_WRITE, MemoryLocation::GpuOnly)
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
            velocity: Self::velocity(gpu, commands, field, copies, face_count)?,
            faces,
            solid: uploaded(
                "wind solid cells",
                &u32_bytes(field.solid.iter().map(|&s| s as u32)),
            )?,
            pressure: device_buffer(
                "wind pressure (ping, pong; the step before's)",
                3 * cell_count as u64,
            )?,
            divergence: device_buffer("wind divergence", cell_count as u64)?,
            sources: Self::sources(gpu, commands, &settings.sources)?,
            conductance,
            coarse: device_buffer(
                "wind multigrid coarse levels (pressure, right-hand side)",
                2 * coarse_cells,
            )?,
            levels,
            canopy: device_buffer("wind canopy frontal area (fixed point)", cell_count as u64)?,
            colliders: crate::compute::colliders::buffer(gpu, "wind colliders")?,
            // One zero without turbulence (forces.comp reads 0 past it).
            turbulence_added: device_buffer(
                "wind turbulence added per face",
                if settings.turbulence.is_some() {
                    face_count as u64
                } else {
                    1
                },
            )?,
            solve: Self::solve(gpu, commands, v_cycle_dispatches)?,
            modes: modes_buffer(gpu, "wind turbulence modes", turbulence::MODES)?,
            subgrid_modes: modes_buffer(
                gpu,
                "wind turbulence sub-grid modes",
                turbulence::SUBGRID_MODES,
            )?,
        };
        let rec = commands.begin()?;
        if at_rest(field) {
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

    /// The velocity's copies: cleared after (at rest), or each the air as
    /// it starts with an oblique inflow or over terrain (`WindField::new`).
    fn velocity(
        gpu: &Gpu,
        commands: &CommandPool,
        field: &WindField,
        copies: u64,
        face_count: u32,
    ) -> Result<Buffer> {
        if at_rest(field) {
            return Buffer::new(
                gpu,
                "wind velocity",
                4 * copies * face_count as u64,
                READ_WRITE,
                MemoryLocation::GpuOnly,
            );
        }
        let copy: Vec<f32> = field.vel.iter().flatten().copied().collect();
        let all = copy.repeat(copies as usize);
        Buffer::with_data(
            gpu,
            commands,
            "wind velocity",
            bytemuck::cast_slice(&all),
            READ_WRITE,
            Access::COMPUTE_READ_WRITE,
        )
    }

    /// What the faces' classification decides, uploaded: the face kinds,
    /// the multigrid's conductances and its level table.
    pub(super) fn classified(
        gpu: &Gpu,
        commands: &CommandPool,
        field: &WindField,
    ) -> Result<[Buffer; 3]> {
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
    pub(super) fn record_classification(
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
            rec.update_buffer(buffer, 0, words);
        }
        Ok(())
    }

    /// The solve buffer: a zero head, the live dispatches zero until a
    /// step's start copies the ones made, which follow.
    fn solve(gpu: &Gpu, commands: &CommandPool, dispatches: &[[u32; 4]]) -> Result<Buffer> {
        let head = MgSolve {
            dispatches: dispatches.len() as u32,
            ..MgSolve::zeroed()
        };
        let mut bytes = bytemuck::bytes_of(&head).to_vec();
        bytes.extend(std::iter::repeat_n(0u8, 16 * dispatches.len()));
        bytes.extend_from_slice(bytemuck::cast_slice(dispatches));
        Buffer::with_data(
            gpu,
            commands,
            "wind multigrid solve (its head, the V-cycle's dispatches)",
            &bytes,
            READ_WRITE | vk::BufferUsageFlags::INDIRECT_BUFFER,
            Access::COMPUTE_READ_WRITE,
        )
    }

    /// The sources as the kernels read them, uploaded; at least one
    /// entry (zeroed) so that the binding is never empty.
    pub(super) fn sources(
        gpu: &Gpu,
        commands: &CommandPool,
        sources: &[WindSource],
    ) -> Result<Buffer> {
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

    /// What each binding of the wind kernels' set holds, in binding order
    /// (glsl/wind/wind_kernel.glsl names them): velocity (two copies), face
    /// kinds, solid cells, pressure (two copies), divergence, sources,
    /// multigrid face conductances, multigrid coarse pressure and
    /// right-hand side, multigrid level table, canopy (the grass's frontal
    /// area per cell), colliders, what the last step's turbulence added,
    /// the turbulence's modes, the multigrid's solve.
    pub(super) fn bound(&self) -> [Bound<'_>; 14] {
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
            Bound::Buffer(&self.solve),
        ]
    }
}

/// Room for `count` turbulence modes, written by each step.
fn modes_buffer(gpu: &Gpu, name: &str, count: usize) -> Result<Buffer> {
    Buffer::new(
        gpu,
        name,
        (count * std::mem::size_of::<TurbulenceMode>()) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
}

/// What the solver's own buffers are used as: read and written by the
/// kernels, cleared and read back by transfers.
const READ_WRITE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw(),
);

/// Whether the air starts at rest (cleared on the GPU), not with an
/// oblique inflow's or an inflow over terrain's velocity (uploaded).
fn at_rest(field: &WindField) -> bool {
    field.vel.iter().flatten().all(|&v| v == 0.0)
}
