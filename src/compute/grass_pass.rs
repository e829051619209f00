//! The grass dynamics on GPU compute (paper section 4): glsl/grass/step.comp,
//! one invocation per blade, recorded into the frame's command buffer right
//! after the wind step. It samples the wind velocity buffer at each tip and
//! writes the deformed control points into the vertex buffer the blade
//! pipeline draws: the vertex data never goes through the CPU.
//!
//! With colliders, the colliders are binned first (`ColliderBins`), and
//! step.comp leaves the blades near one or pressed to a second kernel,
//! glsl/grass/step_touching.comp, dispatched indirectly over the list it
//! made: the blades that touch nothing never run the contact's code, which
//! a device running blades in SIMD lanes would otherwise pay for in every
//! lane (glsl/grass/step.glsl).
//!
//! With two-way coupling it also lays each blade's frontal area into the
//! wind's canopy buffer (src/model/canopy.rs), which the next wind step's
//! advection reads as drag.
//!
//! The pass binds buffers it does not own (the vertex buffer, the wind
//! velocity and canopy): its sets keep them alive.

use ash::vk;
use glam::Vec2;

use std::ops::Range;
use std::sync::Arc;

use crate::compute::collider_bins::{BinGrid, ColliderBins};
use crate::compute::wind_pass::{grid_params, WindInput};
use crate::error::{try_collect, Error, Result};
use crate::gpu::{
    part, Access, Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Gpu, LayoutBinding,
    Pipeline, PipelineLayout, Recording,
};
use crate::interface::{GrassPush, GRASS_GROUP};
use crate::model::contact::{press_decay, Collider, Press};
use crate::model::grass::{substeps, CapCounts, GrassBlade, GrassState};
use crate::model::BladeVertex;
use crate::shaders::Spirv;
/// Bytes of the largest per-blade part the kernel binds (the rest shape
/// and physics, the state, the four control points): what limits a batch.
const BLADE_BYTES_BOUND: u64 = {
    let a = std::mem::size_of::<GrassBlade>();
    let b = std::mem::size_of::<GrassState>();
    let c = 4 * std::mem::size_of::<BladeVertex>();
    let ab = if a > b { a } else { b };
    (if ab > c { ab } else { c }) as u64
};
/// Any motion at its cap, then swing, bend A, bend B, twist.
const CAP_COUNTERS: usize = 5;

/// The grass kernels: every blade, and with colliders the blades they
/// touch.
const GRASS_KERNELS: [&Spirv; 2] = [
    &crate::shaders::GRASS_STEP_COMP,
    &crate::shaders::GRASS_STEP_TOUCHING_COMP,
];

/// Set 0 of the grass kernels, as they use it (build.rs's reflection of
/// glsl/grass/*.comp): what binding b holds is `grass_bound`'s b-th.
pub fn grass_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&GRASS_KERNELS, 0)
}

/// Words each batch's list of touching blades has beyond one per blade:
/// the indirect dispatch (3) and the count before its blades, padding
/// after them, so that the next batch's list starts at a multiple of the
/// 256 bytes any storage offset alignment divides.
const TOUCHING_HEADER_WORDS: u32 = 64;

pub struct GrassPass {
    // One set per batch of blades (`gpu::batches`): a million blades are
    // more than lavapipe lets one binding reach.
    batches: Vec<(DescriptorSet, Range<u32>)>,
    /// Every blade, but those near a collider or pressed it lists.
    pipeline: Pipeline,
    /// The listed blades, with the contact; only with colliders.
    touching_pipeline: Option<Pipeline>,
    /// Per batch, from the byte offset of its entry in `touching_offsets`:
    /// the indirect dispatch, the count and the blades near a collider
    /// or pressed (a placeholder without colliders).
    touching: Buffer,
    touching_offsets: Vec<u64>,
    /// The rest shapes and physics the kernel reads, in slot order.
    blades: Buffer,
    /// The blade each slot steps (`place_order::by_place`): the states
    /// and pressed states lie in this order.
    order: Vec<u32>,
    states: Buffer,
    /// Blade-steps at an angle cap: any motion, then each motion.
    caps: Buffer,
    /// What one dispatch of each kernel (`GRASS_KERNELS`) does to the
    /// buffers its set binds, from build.rs's reflection: the recording
    /// derives the barriers between batches and kernels, and against the
    /// wind step, the binning, the cull pass and the draws, from these and
    /// theirs. The touching kernel's indirect read of its list is its
    /// dispatch's own (`Recording::dispatch_indirect`).
    kernel_uses: [Vec<BufferUse>; 2],
    /// Each blade's pressed state (a placeholder without colliders).
    presses: Buffer,
    /// The colliders, evaluated and binned before each step.
    bins: ColliderBins,
    push: GrassPush,
    blade_count: u32,
    /// Whether each blade keeps its slot (`in_slots`).
    in_slots: bool,
}

/// What a pass whose blades keep their slots is made for
/// (`GrassPass::in_slots`).
pub struct SlotsSetup<'a> {
    pub blades: &'a [GrassBlade],
    /// The colliders it will meet (the viewer's ball among them), so that
    /// each blade keeps a pressed state.
    pub colliders: &'a [Collider],
    /// The simulation step (s).
    pub dt: f32,
    /// The lowest and highest corner (x, z) of the square the roots lie in.
    pub square: (Vec2, Vec2),
}

/// What `GrassPass::made` makes a pass of.
struct Made<'a> {
    blades: &'a [GrassBlade],
    colliders: &'a [Collider],
    dt: f32,
    square: Option<(Vec2, Vec2)>,
}

/// The grass step's layout and kernel, and with colliders the kernel
/// that steps only the blades they touch.
fn step_pipelines(
    gpu: &Gpu,
    has_colliders: bool,
) -> Result<(Arc<PipelineLayout>, Pipeline, Option<Pipeline>)> {
    let layout = PipelineLayout::new::<GrassPush>(
        gpu,
        &grass_set(),
        vk::ShaderStageFlags::COMPUTE,
        "grass",
    )?;
    let pipeline = Pipeline::compute(gpu, &layout, GRASS_KERNELS[0])?;
    let touching = has_colliders
        .then(|| Pipeline::compute(gpu, &layout, GRASS_KERNELS[1]))
        .transpose()?;
    Ok((layout, pipeline, touching))
}

/// What the grass step binds beside its own buffers' batches.
struct GrassBound<'a> {
    buffers: &'a StepBuffers,
    vertices: &'a Buffer,
    wind: &'a Buffer,
    canopy: &'a Buffer,
    subgrid_modes: &'a Buffer,
    bins: &'a ColliderBins,
    touching: &'a Buffer,
    has_colliders: bool,
}

/// One set per batch of `blade_count` blades (`batch_len` a batch).
fn grass_sets(
    gpu: &Gpu,
    layout: &PipelineLayout,
    bound: &GrassBound,
    blade_count: u32,
    batch_len: u32,
) -> Result<Vec<(DescriptorSet, Range<u32>)>> {
    crate::gpu::sets_per_batch(
        gpu,
        layout,
        &grass_set(),
        blade_count,
        BLADE_BYTES_BOUND,
        "grass descriptor set",
        |blades| grass_bound(bound, blades, batch_len),
    )
}

/// What the grass kernels' set binds for the batch of `blades`, in binding
/// order: its part of the per-blade buffers (and of the touching lists),
/// the rest whole. The blades (rest shape and physics), their states, the
/// vertices (the blade pipeline's vertex buffer), the wind velocity, the
/// angle-cap counters, the canopy (frontal area per wind cell), the
/// pressed states, the colliders' states at the step's end, their bins,
/// the touching lists, each slot's blade, the turbulence's modes finer
/// than the wind grid (or a placeholder).
fn grass_bound<'a>(bound: &GrassBound<'a>, blades: &Range<u32>, batch_len: u32) -> Vec<Bound<'a>> {
    use std::mem::size_of;
    let b = bound.buffers;
    vec![
        part(&b.blades, blades, size_of::<GrassBlade>()),
        part(&b.states, blades, size_of::<GrassState>()),
        part(bound.vertices, blades, 4 * size_of::<BladeVertex>()),
        Bound::Buffer(bound.wind),
        Bound::Buffer(&b.caps),
        Bound::Buffer(bound.canopy),
        if bound.has_colliders {
            part(&b.presses, blades, size_of::<Press>())
        } else {
            Bound::Buffer(&b.presses)
        },
        Bound::Buffer(bound.bins.states()),
        Bound::Buffer(bound.bins.bins()),
        if bound.has_colliders {
            Bound::Part {
                buffer: bound.touching,
                offset: list_start(blades, batch_len),
                size: 4 * (TOUCHING_HEADER_WORDS + blades.len() as u32) as u64,
            }
        } else {
            Bound::Buffer(bound.touching)
        },
        part(&b.vertex_slots, blades, size_of::<u32>()),
        Bound::Buffer(bound.subgrid_modes),
    ]
}

impl GrassPass {
    /// Uploads the blades and their rest state and builds the kernel.
    /// `vertices` must hold 4 `BladeVertex` per blade; `wind.velocity`
    /// holds velocity copies in the layout of glsl/common/wind_grid.glsl
    /// for `wind.grid`. The simulation step is `dt`; substeps follow from
    /// the stiffest blade (`model::grass::substeps`). With colliders the
    /// blades are stepped in place order (`place_order::by_place`).
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        blades: &[GrassBlade],
        vertices: &Buffer,
        wind: &WindInput,
        colliders: &[Collider],
        dt: f32,
    ) -> Result<Self> {
        let made = Made {
            blades,
            colliders,
            dt,
            square: None,
        };
        Self::made(gpu, commands, made, vertices, wind)
    }

    /// A pass whose blades keep their slots whatever the colliders (the
    /// cover's kept tiles: `record_replace` puts a tile coming in where
    /// the one leaving was), their roots within `square` (x, z: lowest
    /// and highest corner), which `set_square` moves.
    pub fn in_slots(
        gpu: &Gpu,
        commands: &CommandPool,
        setup: SlotsSetup<'_>,
        vertices: &Buffer,
        wind: &WindInput,
    ) -> Result<Self> {
        let made = Made {
            blades: setup.blades,
            colliders: setup.colliders,
            dt: setup.dt,
            square: Some(setup.square),
        };
        Self::made(gpu, commands, made, vertices, wind)
    }

    fn made(
        gpu: &Gpu,
        commands: &CommandPool,
        made: Made<'_>,
        vertices: &Buffer,
        wind: &WindInput,
    ) -> Result<Self> {
        let Made {
            blades,
            colliders,
            dt,
            square,
        } = made;
        let blade_count = check_blades(blades, vertices)?;
        super::colliders::check_count(colliders)?;
        let bin_grid = match square {
            Some((low, high)) => BinGrid::over_square(low, high, blades),
            None => BinGrid::covering(blades),
        };
        let push = grass_push(
            wind,
            colliders,
            &bin_grid,
            blade_count,
            substeps(blades, dt)?,
            dt,
        );
        // Host memory first: failing here leaves nothing on the GPU to undo.
        let batch_len = crate::gpu::batches::storage_batch_len(gpu, BLADE_BYTES_BOUND)?;
        let ranges = crate::gpu::batches::batches(blade_count, batch_len)?;
        let in_place_order = square.is_none() && !colliders.is_empty();
        let placed = Placed::new(blades, &ranges, in_place_order)?;
        let order = placed.order.clone();
        let buffers = StepBuffers::new(gpu, commands, blades.len(), placed, colliders)?;
        let canopy = wind.canopy.map_or(&buffers.no_canopy, |(buffer, _)| buffer);
        let subgrid_modes = wind
            .subgrid
            .map_or(&buffers.no_subgrid, |(buffer, _)| buffer);
        let bins = ColliderBins::new(gpu, bin_grid, colliders)?;
        let has_colliders = !colliders.is_empty();
        let (layout, pipeline, touching_pipeline) = step_pipelines(gpu, has_colliders)?;
        let touching = touching_lists(gpu, has_colliders, blade_count, batch_len)?;
        let bound = GrassBound {
            buffers: &buffers,
            vertices,
            wind: wind.velocity,
            canopy,
            subgrid_modes,
            bins: &bins,
            touching: &touching,
            has_colliders,
        };
        let batches = grass_sets(gpu, &layout, &bound, blade_count, batch_len)?;
        // Every batch binds parts of the same buffers: the first's say
        // what each kernel touches.
        let first = grass_bound(&bound, &(0..blade_count.min(batch_len)), batch_len);
        let kernel_uses = GRASS_KERNELS.map(|kernel| kernel.buffer_uses(0, &first));
        let touching_offsets = batches
            .iter()
            .map(|(_, blades)| list_start(blades, batch_len))
            .collect();
        Ok(Self {
            batches,
            pipeline,
            touching_pipeline,
            touching,
            touching_offsets,
            kernel_uses,
            blades: buffers.blades,
            order,
            states: buffers.states,
            caps: buffers.caps,
            presses: buffers.presses,
            bins,
            push,
            blade_count,
            in_slots: square.is_some(),
        })
    }

    pub fn blade_count(&self) -> u32 {
        self.blade_count
    }

    /// Replaces the rest shapes and physics of blades `first..` with
    /// `blades`, written in the command buffer ahead of the next step (the
    /// cover's tiles coming into its simulated square), their pressed
    /// states at rest; their states are the caller's to set. Only for a
    /// pass whose blades keep their slots (`in_slots`), or one made
    /// without colliders (whose slots are the blades' own order).
    pub fn record_replace(
        &mut self,
        rec: &Recording,
        first: u32,
        blades: &[GrassBlade],
    ) -> Result<()> {
        if self.presses_live() && !self.in_slots {
            return Err(Error::InvalidInput(
                "a grass step made with colliders keeps its blades in place order; its blades cannot be replaced".into(),
            ));
        }
        if first as u64 + blades.len() as u64 > self.blade_count as u64 {
            return Err(Error::InvalidInput(format!(
                "blades {first}..{} are beyond the grass step's {}",
                first as u64 + blades.len() as u64,
                self.blade_count
            )));
        }
        self.bins.widen_reach(blades);
        let size = std::mem::size_of::<GrassBlade>();
        let offset = (first as usize * size) as u64;
        rec.update_buffer(&self.blades, offset, bytemuck::cast_slice(blades));
        if self.presses_live() {
            // At rest: unpressed, untouched (every bit zero).
            let size = std::mem::size_of::<Press>() as u64;
            let bytes = blades.len() as u64 * size;
            rec.fill_range(&self.presses, first as u64 * size, bytes, 0);
        }
        Ok(())
    }

    /// Moves the square the roots lie in (`in_slots`) to start at `low`
    /// (x, z) from the next step on: the colliders' bins follow it.
    pub fn set_square(&mut self, low: Vec2) {
        self.bins.set_corner(low);
        self.push.bin_corner = self.bins.grid().corner.to_array();
    }

    /// Each blade's pressed state, in slot order (None for a pass made
    /// without colliders, which keeps none).
    pub fn presses(&self) -> Option<&Buffer> {
        self.presses_live().then_some(&self.presses)
    }

    /// The rest shapes and physics in slot order (for a kernel that sets
    /// states; declared by its user).
    pub fn blades(&self) -> &Buffer {
        &self.blades
    }

    /// The angles and angular velocities in slot order, which the next
    /// step reads and writes (declared by any other user).
    pub fn states(&self) -> &Buffer {
        &self.states
    }

    /// Whether each blade keeps a pressed state (made with colliders).
    fn presses_live(&self) -> bool {
        self.push.pressed_states != 0
    }

    /// The colliders from the next recorded step on (the viewer's ball
    /// coming, going, steered): written in the command buffer, no upload.
    /// A pass made without colliders has no pressed states to give blades
    /// and refuses any.
    pub fn set_colliders(&mut self, colliders: &[Collider]) -> Result<()> {
        if !colliders.is_empty() && !self.presses_live() {
            return Err(Error::InvalidInput(
                "this grass step was made without colliders and keeps no pressed state; \
                 make it with the colliders it will meet"
                    .into(),
            ));
        }
        self.bins.set_colliders(colliders)
    }

    /// The colliders' bins (for tests).
    pub fn collider_bins(&self) -> &ColliderBins {
        &self.bins
    }

    /// Symplectic Euler substeps per simulation step.
    pub fn substeps(&self) -> u32 {
        self.push.substeps
    }

    /// Raises the substeps, from the next step on, to what `blades` need
    /// (`model::grass::substeps`) where that is more: blades coming in
    /// stiffer than any stepped so far (the cover's tiles entering its
    /// simulated square). Never lowers them.
    pub fn raise_substeps_for(&mut self, blades: &[GrassBlade]) -> Result<()> {
        let needed = substeps(blades, self.push.dt)?;
        if needed > self.push.substeps {
            self.push.substeps = needed;
            self.push.substep = self.push.dt / needed as f32;
        }
        Ok(())
    }

    /// The wind grid's corner from the next step on: the wind window
    /// moved under the camera (`WindPass::record_shift`).
    pub fn set_wind_origin(&mut self, origin: glam::Vec3) {
        self.push.grid.origin = origin.to_array();
    }

    /// Records one simulation step, sampling the wind velocity copy that
    /// starts `wind_offset` floats into the wind buffer (0 for `WindPass`'s
    /// state): with colliders, their binning (`ColliderBins::record`), the
    /// lists emptied, step.comp, then step_touching.comp over each
    /// batch's list. Each dispatch declares what it touches
    /// (`kernel_uses`); whoever reads the vertices next declares that.
    ///
    /// `end_time` is the simulated time at the step's end, where the
    /// colliders stand (`contact::step_end_time`).
    pub fn record_step(&self, rec: &Recording, wind_offset: u32, end_time: f32) {
        let mut push = self.push;
        push.wind_offset = wind_offset;
        push.end_time = end_time;
        push.collider_count = self.bins.count();
        self.bins.record(rec, end_time);
        if self.touching_pipeline.is_some() {
            // Empty lists, after the last step's dispatch and reads.
            for &offset in &self.touching_offsets {
                rec.update_buffer(&self.touching, offset, &[0, 1, 1, 0]);
            }
        }
        rec.bind_pipeline(&self.pipeline);
        for (set, blades) in &self.batches {
            // The batches share the cap counters and the canopy.
            rec.uses(&self.kernel_uses[0]);
            push.blade_count = blades.len() as u32;
            rec.bind_set(&self.pipeline, set);
            rec.push_constants(&self.pipeline, &push);
            rec.dispatch(push.blade_count.div_ceil(GRASS_GROUP));
        }
        if let Some(touching_pipeline) = &self.touching_pipeline {
            rec.bind_pipeline(touching_pipeline);
            for ((set, blades), &offset) in self.batches.iter().zip(&self.touching_offsets) {
                push.blade_count = blades.len() as u32;
                rec.bind_set(touching_pipeline, set);
                rec.push_constants(touching_pipeline, &push);
                rec.dispatch_indirect(&self.touching, offset, &self.kernel_uses[1]);
            }
        }
    }

    /// The blade-steps at an angle cap over the `steps` steps recorded so
    /// far (the counters cover every step since the pass was made).
    pub fn read_caps(&self, gpu: &Gpu, commands: &CommandPool, steps: u64) -> Result<CapCounts> {
        let c: Vec<u32> = self.caps.read_back(gpu, commands, CAP_COUNTERS)?;
        Ok(CapCounts {
            blade_steps: steps * self.blade_count as u64,
            at_cap: c[0] as u64,
            swing: c[1] as u64,
            bend_a: c[2] as u64,
            bend_b: c[3] as u64,
            twist: c[4] as u64,
        })
    }

    /// How many blades the last recorded step stepped with the contact
    /// (near a collider or pressed): 0 for a pass made without colliders.
    pub fn read_touching(&self, gpu: &Gpu, commands: &CommandPool) -> Result<u64> {
        if self.touching_pipeline.is_none() {
            return Ok(0);
        }
        let words: Vec<u32> =
            self.touching
                .read_back(gpu, commands, (self.touching.size / 4) as usize)?;
        Ok(self
            .touching_offsets
            .iter()
            .map(|&offset| words[offset as usize / 4 + 3] as u64)
            .sum())
    }

    /// Every blade's pressed state (for tests; empty for a pass made
    /// without colliders).
    pub fn read_presses(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<Press>> {
        if !self.presses_live() {
            return Ok(Vec::new());
        }
        let placed = self
            .presses
            .read_back(gpu, commands, self.blade_count as usize)?;
        Ok(self.in_scene_order(placed))
    }

    /// Every blade's angles and angular velocities (for tests and reports).
    pub fn read_states(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<GrassState>> {
        let placed = self
            .states
            .read_back(gpu, commands, self.blade_count as usize)?;
        Ok(self.in_scene_order(placed))
    }

    /// Per-slot values (place order) in the blades' scene order.
    fn in_scene_order<T: Copy + Default>(&self, placed: Vec<T>) -> Vec<T> {
        let mut out = vec![T::default(); placed.len()];
        for (value, &blade) in placed.into_iter().zip(&self.order) {
            out[blade as usize] = value;
        }
        out
    }
}

/// Bytes one grass step must move at least for `blades` blades: each
/// blade's rest shape and physics read, its slot's index read, its state
/// read and written, its four control points written (the substeps run
/// in registers). The wind grid it samples (under a MiB, held in caches),
/// the cap counters and the colliders' lists are not counted: this is the
/// memory-bandwidth floor's numerator.
pub fn bytes_per_step(blades: usize) -> u64 {
    use std::mem::size_of;
    let per_blade = size_of::<GrassBlade>()
        + size_of::<u32>()
        + 2 * size_of::<GrassState>()
        + 4 * size_of::<BladeVertex>();
    blades as u64 * per_blade as u64
}

/// Device memory the grass of `blades` blades needs: the vertex buffer the
/// pipeline draws, the rest shapes with physics, the slots' indices, the
/// state, and with colliders each blade's pressed state and a place on
/// the touching list.
pub fn device_bytes(blades: usize, with_colliders: bool) -> u64 {
    use std::mem::size_of;
    let mut per_blade = 4 * size_of::<BladeVertex>()
        + size_of::<GrassBlade>()
        + size_of::<u32>()
        + size_of::<GrassState>();
    if with_colliders {
        per_blade += size_of::<Press>() + size_of::<u32>();
    }
    blades as u64 * per_blade as u64
}

/// The blade count, refused where the kernels cannot step it or
/// `vertices` cannot hold 4 `BladeVertex` per blade.
fn check_blades(blades: &[GrassBlade], vertices: &Buffer) -> Result<u32> {
    let blade_count = u32::try_from(blades.len())
        .ok()
        .filter(|&n| n > 0 && n <= u32::MAX / 4)
        .ok_or_else(|| {
            Error::InvalidInput(format!("{} blades cannot be simulated", blades.len()))
        })?;
    let needed = blades.len() as u64 * 4 * std::mem::size_of::<BladeVertex>() as u64;
    if vertices.size < needed {
        return Err(Error::InvalidInput(format!(
            "the vertex buffer holds {} bytes, {needed} needed for {} blades",
            vertices.size,
            blades.len()
        )));
    }
    Ok(blade_count)
}

/// The step's push constants as far as they hold for every step: the
/// wind's offset, the step's end time and the colliders' count are set at
/// each (`GrassPass::record_step`).
fn grass_push(
    wind: &WindInput,
    colliders: &[Collider],
    bin_grid: &BinGrid,
    blade_count: u32,
    substeps: u32,
    dt: f32,
) -> GrassPush {
    let grid = &wind.grid;
    GrassPush {
        grid: grid_params(grid, grid.face_count() as u32),
        blade_count,
        substeps,
        lay_canopy: wind.canopy.is_some() as u32,
        dt,
        substep: dt / substeps as f32,
        canopy_unit: wind.canopy.map_or(0.0, |(_, unit)| unit),
        press_decay: press_decay(dt),
        pressed_states: !colliders.is_empty() as u32,
        bin_per_metre: bin_grid.per_metre,
        bin_corner: bin_grid.corner.to_array(),
        bin_columns: bin_grid.columns,
        bin_rows: bin_grid.rows,
        subgrid_modes: wind.subgrid.map_or(0, |(_, count)| count),
        ..GrassPush::default()
    }
}

/// The blades in the order the kernels step them (`place_order`), each
/// writing its control points at its own index: the order, the blades in
/// it, and each slot's blade index within its batch.
struct Placed {
    order: Vec<u32>,
    blades: Vec<GrassBlade>,
    vertex_slots: Vec<u32>,
}

impl Placed {
    /// `in_place_order`: with colliders, neighbours stepped together, so
    /// that the blades near one fill whole SIMD groups. Otherwise (every
    /// blade taking the same path without colliders, or the cover's
    /// blades, which keep their slots and lie tile by tile) scene order,
    /// which keeps the control points' writes contiguous.
    fn new(blades: &[GrassBlade], ranges: &[Range<u32>], in_place_order: bool) -> Result<Self> {
        let count = blades.len();
        let order = if in_place_order {
            super::place_order::by_place(blades, ranges)
        } else {
            try_collect(count, 0..count as u32, "the blades' order")?
        };
        let placed = try_collect(
            count,
            order.iter().map(|&i| blades[i as usize]),
            "the blades in place order",
        )?;
        let mut vertex_slots = try_collect(count, order.iter().copied(), "the blades' order")?;
        for range in ranges {
            for slot in &mut vertex_slots[range.start as usize..range.end as usize] {
                *slot -= range.start;
            }
        }
        Ok(Self {
            order,
            blades: placed,
            vertex_slots,
        })
    }
}

/// The buffers the step owns, uploaded: the blades and their slots, the
/// state at rest, the cap counters, the pressed states and the canopy's
/// placeholder.
struct StepBuffers {
    blades: Buffer,
    vertex_slots: Buffer,
    states: Buffer,
    caps: Buffer,
    /// Bound when the coupling is one-way (a binding must name a live
    /// buffer); the kernel never touches it then.
    no_canopy: Buffer,
    /// Bound when the wind has no modes finer than its grid; never read.
    no_subgrid: Buffer,
    /// Made without colliders, the kernel touches none: one entry. Made
    /// with them, each blade keeps a pressed state even when
    /// `set_colliders` takes them all away, so that it decays.
    presses: Buffer,
}

impl StepBuffers {
    fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        count: usize,
        placed: Placed,
        colliders: &[Collider],
    ) -> Result<Self> {
        let rest = try_collect(
            count,
            std::iter::repeat(GrassState::default()),
            "the grass state",
        )?;
        let press_count = if colliders.is_empty() { 1 } else { count };
        let rest_presses = try_collect(
            press_count,
            std::iter::repeat(Press::default()),
            "the grass pressed state",
        )?;
        // TRANSFER_DST: the cover's kept tiles replace blades and states
        // (`record_replace`).
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let upload = |name: &str, bytes: &[u8], then: Access| {
            Buffer::with_data(gpu, commands, name, bytes, usage, then)
        };
        let blades = upload(
            "grass blades (rest shape, physics; slot order)",
            bytemuck::cast_slice(&placed.blades),
            Access::COMPUTE_READ,
        )?;
        drop(placed.blades);
        Ok(Self {
            blades,
            vertex_slots: upload(
                "grass vertex slots (each blade's index in its batch)",
                bytemuck::cast_slice(&placed.vertex_slots),
                Access::COMPUTE_READ,
            )?,
            states: upload(
                "grass state (angles, angular velocities)",
                bytemuck::cast_slice(&rest),
                Access::COMPUTE_READ_WRITE,
            )?,
            caps: upload(
                "grass angle-cap counters",
                bytemuck::cast_slice(&[0u32; CAP_COUNTERS]),
                Access::COMPUTE_READ_WRITE,
            )?,
            no_canopy: upload(
                "grass canopy placeholder (one-way coupling)",
                &[0u8; 4],
                Access::COMPUTE_READ_WRITE,
            )?,
            no_subgrid: upload(
                "grass sub-grid turbulence placeholder (none)",
                &[0u8; std::mem::size_of::<crate::interface::TurbulenceMode>()],
                Access::COMPUTE_READ,
            )?,
            presses: upload(
                "grass pressed state (colliders)",
                bytemuck::cast_slice(&rest_presses),
                Access::COMPUTE_READ_WRITE,
            )?,
        })
    }
}

/// Where batch `blades`' list of touching blades starts (bytes): batch k's
/// starts TOUCHING_HEADER_WORDS * k words past its first blade, the lists
/// before it taking that many more words than their blades.
fn list_start(blades: &Range<u32>, batch_len: u32) -> u64 {
    4 * (blades.start as u64 + TOUCHING_HEADER_WORDS as u64 * (blades.start / batch_len) as u64)
}

/// The lists of blades near a collider or pressed, each batch's with its
/// indirect dispatch and count (a placeholder without colliders).
fn touching_lists(
    gpu: &Gpu,
    has_colliders: bool,
    blade_count: u32,
    batch_len: u32,
) -> Result<Buffer> {
    let list_words = if has_colliders {
        blade_count as u64 + TOUCHING_HEADER_WORDS as u64 * blade_count.div_ceil(batch_len) as u64
    } else {
        TOUCHING_HEADER_WORDS as u64
    };
    Buffer::new(
        gpu,
        "grass blades touching (near a collider or pressed)",
        4 * list_words,
        vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC,
        crate::gpu::MemoryLocation::GpuOnly,
    )
}
