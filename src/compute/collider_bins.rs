//! Collider binning for the grass step (glsl/grass/bin_colliders.comp):
//! before each step, one invocation per collider evaluates it at the
//! step's end once, and marks it in the cells of a coarse grid over the
//! field's roots that it can reach (its box grown by its radius and the
//! longest blade's reach). Each blade then tests only the colliders of
//! its root's cell, in scene order: a superset of its near colliders
//! (`contact::near_blade`), so the grass step is the same as without
//! bins, at a cost that follows how many colliders are near, not how many
//! there are.
//!
//! The pass owns the colliders' GPU records (written in the command
//! buffer before each binning, `colliders::record_write`), their states at
//! the step's end and the bins; the grass step binds the last two.

use ash::vk;
use glam::{Vec2, Vec3, Vec3Swizzles};

use crate::error::Result;
use crate::gpu::{
    Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Gpu, LayoutBinding, MemoryLocation,
    Pipeline, PipelineLayout, Recording,
};
use crate::interface::{BinPush, GpuColliderState, GRASS_GROUP};
use crate::model::contact::{reach, Collider, ColliderState, GpuCollider, MAX_COLLIDERS};
use crate::model::grass::GrassBlade;
use crate::shaders::Spirv;
/// Cells along the grid's longer side at most: 64 x 64 cells of 16 bytes
/// are 64 KiB, cleared each step.
pub const MAX_CELLS_PER_SIDE: u32 = 64;
/// Metres the grid and each collider's reach are widened by, so that
/// rounding never leaves a root outside the cells its colliders mark.
const MARGIN: f32 = 1e-3;
/// Words per cell: one bit per collider.
const WORDS_PER_CELL: usize = MAX_COLLIDERS / 32;

/// The bins' grid: square cells over the roots' extent in x and z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BinGrid {
    /// The corner at the lowest x and z (m).
    pub corner: Vec2,
    /// Cells per metre.
    pub per_metre: f32,
    pub columns: u32,
    pub rows: u32,
    /// The longest blade's reach, with the margin (m).
    pub reach: f32,
    /// The roots' lowest and highest y (m).
    pub root_y: (f32, f32),
}

impl BinGrid {
    /// The grid over `blades`' roots: cells at least the longest reach
    /// across (a smaller cell would mark more cells for the same
    /// colliders), at most `MAX_CELLS_PER_SIDE` along the longer side.
    pub fn covering(blades: &[GrassBlade]) -> Self {
        let mut low = Vec3::splat(f32::INFINITY);
        let mut high = Vec3::splat(f32::NEG_INFINITY);
        let mut longest = 0.0f32;
        for blade in blades {
            let root = blade.rest_point(0);
            low = low.min(root);
            high = high.max(root);
            longest = longest.max(reach(blade));
        }
        if blades.is_empty() {
            (low, high) = (Vec3::ZERO, Vec3::ZERO);
        }
        Self::over(low.xz(), high.xz(), longest, (low.y, high.y))
    }

    /// The grid over a square whose roots lie within `low`..`high` (x, z)
    /// wherever it moves (`ColliderBins::set_corner`), their heights
    /// anywhere (the cover's kept tiles: the ground under them changes as
    /// the square moves), for blades reaching as far as `blades`'
    /// longest (`ColliderBins::widen_reach` for longer ones coming in).
    pub fn over_square(low: Vec2, high: Vec2, blades: &[GrassBlade]) -> Self {
        let longest = blades.iter().map(reach).fold(0.0f32, f32::max);
        Self::over(low, high, longest, (f32::MIN, f32::MAX))
    }

    /// The grid over roots within `low`..`high` (x, z) and `root_y`, for
    /// blades reaching `longest` at most.
    fn over(low: Vec2, high: Vec2, longest: f32, root_y: (f32, f32)) -> Self {
        let corner = low - MARGIN;
        let extent = (high - low) + 2.0 * MARGIN;
        let cell = (extent.max_element() / (MAX_CELLS_PER_SIDE - 1) as f32).max(longest);
        let per_metre = 1.0 / cell.max(MARGIN);
        // The highest root lies at least the margin inside the last cell
        // (the minimum only guards rounding).
        let side = |length: f32| ((length * per_metre).floor() as u32 + 1).min(MAX_CELLS_PER_SIDE);
        Self {
            corner,
            per_metre,
            columns: side(extent.x),
            rows: side(extent.y),
            reach: longest + MARGIN,
            root_y,
        }
    }

    pub fn cell_count(&self) -> usize {
        (self.columns * self.rows) as usize
    }

    /// The cell a root lies in (`bin_of` in glsl/grass/step.glsl).
    pub fn cell_of(&self, root: Vec3) -> usize {
        let cell = ((Vec2::new(root.x, root.z) - self.corner) * self.per_metre).floor();
        let column = cell.x.clamp(0.0, (self.columns - 1) as f32) as u32;
        let row = cell.y.clamp(0.0, (self.rows - 1) as f32) as u32;
        (row * self.columns + column) as usize
    }
}

/// The binning kernel.
const BIN_KERNEL: &Spirv = &crate::shaders::GRASS_BIN_COLLIDERS_COMP;

/// Set 0 of the binning kernel, as it uses it (build.rs's reflection): the
/// colliders, their states at the step's end, the bins (four words per
/// cell).
pub fn bin_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&[BIN_KERNEL], 0)
}

pub struct ColliderBins {
    set: DescriptorSet,
    pipeline: Pipeline,
    /// What the kernel does to what its set binds (build.rs's reflection).
    kernel_uses: Vec<BufferUse>,
    /// The colliders, with room for `MAX_COLLIDERS`.
    colliders: Buffer,
    states: Buffer,
    bins: Buffer,
    grid: BinGrid,
    /// The colliders as the kernel reads them, written before each
    /// binning.
    records: Vec<GpuCollider>,
}

impl ColliderBins {
    /// Bins over `grid` (`BinGrid::covering` the blades) for `colliders`.
    pub fn new(gpu: &Gpu, grid: BinGrid, colliders: &[Collider]) -> Result<Self> {
        let records = super::colliders::records(colliders)?;
        let colliders_buffer = super::colliders::buffer(gpu, "grass colliders")?;
        let states = Buffer::new(
            gpu,
            "grass collider states (step's end)",
            (MAX_COLLIDERS * std::mem::size_of::<GpuColliderState>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let bins = Buffer::new(
            gpu,
            "grass collider bins",
            (grid.cell_count() * WORDS_PER_CELL * 4) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let layout = PipelineLayout::new::<BinPush>(
            gpu,
            &bin_set(),
            vk::ShaderStageFlags::COMPUTE,
            "grass collider binning",
        )?;
        let pipeline = Pipeline::compute(gpu, &layout, BIN_KERNEL)?;
        let bound = [
            Bound::Buffer(&colliders_buffer),
            Bound::Buffer(&states),
            Bound::Buffer(&bins),
        ];
        let set = DescriptorSet::new(
            gpu,
            &layout,
            &bin_set(),
            &bound,
            "grass collider binning set",
        )?;
        let kernel_uses = BIN_KERNEL.buffer_uses(0, &bound);
        Ok(Self {
            set,
            pipeline,
            kernel_uses,
            colliders: colliders_buffer,
            states,
            bins,
            grid,
            records,
        })
    }

    /// The colliders from the next recorded binning on.
    pub fn set_colliders(&mut self, colliders: &[Collider]) -> Result<()> {
        self.records = super::colliders::records(colliders)?;
        Ok(())
    }

    /// The grid's lowest corner at `low` (x, z) from the next binning on
    /// (a square of roots moved: `BinGrid::over_square`).
    pub fn set_corner(&mut self, low: Vec2) {
        self.grid.corner = low - MARGIN;
    }

    /// Widens the colliders' reach, from the next binning on, to `blades`'
    /// longest where that is more (blades coming in).
    pub fn widen_reach(&mut self, blades: &[GrassBlade]) {
        let longest = blades.iter().map(reach).fold(0.0f32, f32::max) + MARGIN;
        self.grid.reach = self.grid.reach.max(longest);
    }

    /// How many colliders the next binning evaluates.
    pub fn count(&self) -> u32 {
        self.records.len() as u32
    }

    pub fn grid(&self) -> &BinGrid {
        &self.grid
    }

    /// The colliders' states at the step's end, as the grass step reads
    /// them (`ColliderState` in glsl/common/collider.glsl).
    pub fn states(&self) -> &Buffer {
        &self.states
    }

    /// Four words per cell, one bit per collider.
    pub fn bins(&self) -> &Buffer {
        &self.bins
    }

    /// Records the binning for a step ending at `end_time`, declaring what
    /// it writes and reads; the grass kernels' reads of the states and
    /// bins (their reflected uses) order it after the last step's and
    /// before the next step's. Nothing without colliders.
    pub fn record(&self, rec: &Recording, end_time: f32) {
        if self.records.is_empty() {
            return;
        }
        super::colliders::record_write(&self.colliders, rec, &self.records);
        rec.fill_buffer(&self.bins, 0);
        rec.uses(&self.kernel_uses);
        let g = &self.grid;
        let push = BinPush {
            corner: g.corner.to_array(),
            per_metre: g.per_metre,
            end_time,
            columns: g.columns,
            rows: g.rows,
            collider_count: self.count(),
            reach: g.reach,
            root_low: g.root_y.0,
            root_high: g.root_y.1,
        };
        rec.bind_pipeline(&self.pipeline);
        rec.bind_set(&self.pipeline, &self.set);
        rec.push_constants(&self.pipeline, &push);
        rec.dispatch(self.count().div_ceil(GRASS_GROUP));
    }

    /// The bins the last recorded binning left (for tests).
    pub fn read_bins(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<[u32; 4]>> {
        self.bins.read_back(gpu, commands, self.grid.cell_count())
    }

    /// The colliders' states the last recorded binning left (for tests).
    pub fn read_states(&self, gpu: &Gpu, commands: &CommandPool) -> Result<Vec<ColliderState>> {
        let raw: Vec<GpuColliderState> =
            self.states.read_back(gpu, commands, self.records.len())?;
        Ok(raw
            .iter()
            .map(|s| ColliderState {
                a: Vec3::from(s.a),
                b: Vec3::from(s.b),
                radius: s.radius,
                velocity: Vec3::from(s.velocity),
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade_at(x: f32, z: f32, height: f32) -> GrassBlade {
        let at = |i: usize| [x, height * i as f32 / 3.0, z];
        GrassBlade {
            rest_root: at(0),
            rest_1: at(1),
            rest_2: at(2),
            rest_tip: at(3),
            ..GrassBlade::default()
        }
    }

    #[test]
    fn the_grid_holds_every_root_and_its_cells_are_at_least_a_reach_across() {
        let blades: Vec<GrassBlade> = (0..400)
            .map(|i| {
                blade_at(
                    (i % 20) as f32 * 1.5 - 10.0,
                    (i / 20) as f32 * 0.7 + 3.0,
                    0.6,
                )
            })
            .collect();
        let grid = BinGrid::covering(&blades);
        assert!((1.0 / grid.per_metre) >= 0.6 - 1e-6);
        assert!(grid.columns <= MAX_CELLS_PER_SIDE && grid.rows <= MAX_CELLS_PER_SIDE);
        for blade in &blades {
            let root = blade.rest_point(0);
            let cell = (Vec2::new(root.x, root.z) - grid.corner) * grid.per_metre;
            assert!(cell.x >= 0.0 && cell.y >= 0.0, "{root} before the corner");
            assert!(
                cell.x < grid.columns as f32 && cell.y < grid.rows as f32,
                "{root} beyond the last cell"
            );
        }
        // 28.5 m along x in cells of 0.6 m: 48 columns; 13.3 m along z: 23 rows.
        assert_eq!((grid.columns, grid.rows), (48, 23));
    }

    #[test]
    fn a_wide_field_has_at_most_sixty_four_cells_a_side() {
        let blades = [blade_at(0.0, 0.0, 0.5), blade_at(200.0, 50.0, 0.5)];
        let grid = BinGrid::covering(&blades);
        // 200 m in 63 cells (the last root inside the last), or 64 if
        // rounding puts it at the 63rd's far edge.
        assert!(
            (63..=MAX_CELLS_PER_SIDE).contains(&grid.columns),
            "{grid:?}"
        );
        assert_eq!(grid.rows, 16);
        assert_eq!(
            grid.cell_of(Vec3::new(200.0, 0.0, 50.0)),
            grid.cell_count() - 1
        );
        assert_eq!(grid.cell_of(Vec3::ZERO), 0);
    }
}
