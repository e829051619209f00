//! The paper's dynamics near the camera for the cover (`[grass.cover]`'s
//! `simulate_radius`): the tiles whose squares reach within the radius
//! keep their blades' state, stepped by the grass kernel like any patch's
//! (`GrassPass`). Each tile is kept in the state slot its coordinates wrap
//! to (`cover::state_slot`), so a tile keeps its state for as long as it
//! stays in the simulated square, and a tile coming in takes the slot of
//! the one leaving: its blades are made on the CPU (`cover::grass_blade`,
//! the same blades the tile kernel makes) and written in the command
//! buffer, and glsl/cover/enter.comp starts them where the tile kernel
//! showed them the frame before (its last poses, which this pass keeps
//! for it: `far_poses`), or at their quasi-static pose, still. The tile
//! kernel poses the kept blades from their state (their pressing faded
//! out over the band inside the radius: `cover::pressed_fade`), and a
//! blade leaving the square goes on from it.

use ash::vk;
use glam::Vec2;

use crate::compute::grass_pass::SlotsSetup;
use crate::compute::wind_pass::{grid_params, WindInput};
use crate::compute::GrassPass;
use crate::error::{Error, Result};
use crate::gpu::{
    Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Gpu, LayoutBinding, MemoryLocation,
    Pipeline, PipelineLayout, Recording,
};
use crate::interface::{CoverEnterPush, FarPose, COVER_GROUP};
use crate::model::contact::Collider;
use crate::model::grass::GrassBlade;
use crate::model::terrain::Terrain;
use crate::model::wind::WindGrid;
use crate::model::BladeVertex;
use crate::scene::cover::{self, CoverTiles};
use crate::scene::{BladeShape, Cover, Grass, GrassDynamics};
use crate::shaders::Spirv;

/// The kernel that starts the blades of a tile coming in.
const ENTER_KERNEL: &Spirv = &crate::shaders::COVER_ENTER_COMP;

/// Set 0 of the enter kernel, as it uses it (build.rs's reflection): the
/// dynamics' blades, their states, the wind velocity, the tile kernel's
/// last poses (`FarPose`).
pub fn cover_enter_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&[ENTER_KERNEL], 0)
}

pub struct CoverDynamics {
    /// The kept tiles' blades, stepped as the patches' are; its control
    /// points go to `_stepped`, which nothing draws (the tile kernel poses
    /// the blades from their states).
    grass: GrassPass,
    enter: Pipeline,
    enter_set: DescriptorSet,
    /// The tile kernel's last pose of every cover blade
    /// (`CoverTilePass`'s, kept here so that a tile coming in starts
    /// from it; a placeholder where the device cannot bind them whole:
    /// `far_kept` false), and the whole square's side it is laid out by.
    far_poses: Buffer,
    far_kept: bool,
    far_side: u32,
    _stepped: Buffer,
    /// What the enter kernel does to what its set binds (build.rs's
    /// reflection).
    enter_uses: Vec<BufferUse>,
    grid: WindGrid,
    cover: Cover,
    /// Makes the blades of a tile coming in.
    maker: TileMaker,
    /// The tile each state slot holds.
    kept: Vec<[i32; 2]>,
    /// The slots whose blades the next step starts at their quasi-static
    /// pose.
    entering: Vec<u32>,
    square: CoverTiles,
}

/// What the cover's dynamics are made for.
pub struct CoverDynamicsSetup<'a> {
    pub cover: &'a Cover,
    /// The cover's seed as the tile kernel takes it (`cover::seed32`).
    pub seed: u32,
    /// The scene's blade shapes and physics ranges.
    pub grass: &'a Grass,
    /// The simulation step (s).
    pub dt: f32,
    /// Where the camera starts (x, z).
    pub camera: Vec2,
    /// The ground the blades are rooted on.
    pub terrain: &'a Terrain,
    /// The colliders the kept blades will meet (the viewer's ball among
    /// them), so that each keeps a pressed state.
    pub colliders: &'a [Collider],
}

/// The blades of the tiles kept in `square`, each tile's in the slot it
/// wraps to (`cover::state_slot`), and each slot's tile: refused where
/// they are more than one storage binding holds.
fn kept_blades(
    gpu: &Gpu,
    cover: &Cover,
    maker: &TileMaker,
    square: &CoverTiles,
) -> Result<(Vec<[i32; 2]>, Vec<GrassBlade>)> {
    let count = square.blade_count();
    let bytes = count * std::mem::size_of::<GrassBlade>() as u64;
    let range = gpu.limits().max_storage_buffer_range as u64;
    if bytes > range {
        return Err(Error::InvalidInput(format!(
            "grass.cover.simulate_radius {} m at {} blades a square metre keeps {count} blades in the dynamics ({bytes} bytes of blades), more than one storage binding of this device holds ({range}); lower simulate_radius or density",
            cover.simulate_radius(),
            cover.density()
        )));
    }
    let side = square.side;
    let mut kept = vec![[0, 0]; square.tile_count() as usize];
    let mut blades = vec![GrassBlade::default(); count as usize];
    for n in 0..square.tile_count() as u32 {
        let tile = square.tile(n);
        let slot = cover::state_slot(tile, side);
        kept[slot as usize] = tile;
        let first = (slot * square.per_tile) as usize;
        let made = maker.blades(tile, square.per_tile)?;
        blades[first..first + made.len()].copy_from_slice(&made);
    }
    Ok((kept, blades))
}

impl CoverDynamics {
    /// The dynamics of the cover's blades within its `simulate_radius` of
    /// the camera, in `wind`.
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        setup: CoverDynamicsSetup<'_>,
        wind: &WindInput,
    ) -> Result<Self> {
        let CoverDynamicsSetup {
            cover,
            seed,
            grass,
            dt,
            camera,
            terrain,
            colliders,
        } = setup;
        let maker = TileMaker {
            terrain: terrain.clone(),
            seed,
            shape: grass.shape.clone(),
            dynamics: grass.dynamics.clone(),
        };
        let square = cover::kept_tiles(cover, camera);
        let count = square.blade_count();
        let (kept, blades) = kept_blades(gpu, cover, &maker, &square)?;
        let stepped = Buffer::new(
            gpu,
            "cover dynamics control points (not drawn)",
            count * 4 * std::mem::size_of::<BladeVertex>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let slots = SlotsSetup {
            blades: &blades,
            colliders,
            dt,
            square: square.extent(),
        };
        let grass_pass = GrassPass::in_slots(gpu, commands, slots, &stepped, wind)?;
        let layout = PipelineLayout::new::<CoverEnterPush>(
            gpu,
            &cover_enter_set(),
            vk::ShaderStageFlags::COMPUTE,
            "cover enter",
        )?;
        let enter = Pipeline::compute(gpu, &layout, ENTER_KERNEL)?;
        let (far_poses, far_kept) = far_poses_buffer(gpu, commands, cover)?;
        let bound = [
            Bound::Buffer(grass_pass.blades()),
            Bound::Buffer(grass_pass.states()),
            Bound::Buffer(wind.velocity),
            Bound::Buffer(&far_poses),
        ];
        let enter_set =
            DescriptorSet::new(gpu, &layout, &cover_enter_set(), &bound, "cover enter set")?;
        let enter_uses = ENTER_KERNEL.buffer_uses(0, &bound);
        Ok(Self {
            grass: grass_pass,
            enter,
            enter_set,
            far_poses,
            far_kept,
            far_side: CoverTiles::around(cover, camera).side,
            _stepped: stepped,
            enter_uses,
            grid: wind.grid,
            cover: cover.clone(),
            maker,
            kept,
            entering: (0..square.tile_count() as u32).collect(),
            square,
        })
    }

    /// Keeps the tiles around a camera at `camera` (x, z): each tile come
    /// into the simulated square replaces the one that left its slot, its
    /// blades written in the command buffer; they start at their
    /// quasi-static pose before the next step.
    pub fn record_follow(&mut self, rec: &Recording, camera: Vec2) -> Result<()> {
        let square = cover::kept_tiles(&self.cover, camera);
        for n in 0..square.tile_count() as u32 {
            let tile = square.tile(n);
            let slot = cover::state_slot(tile, square.side);
            if self.kept[slot as usize] == tile {
                continue;
            }
            let blades = self.maker.blades(tile, square.per_tile)?;
            // A blade stiffer than any stepped so far raises the
            // substeps for all (the first square's stiffest set them).
            self.grass.raise_substeps_for(&blades)?;
            self.grass
                .record_replace(rec, slot * square.per_tile, &blades)?;
            self.kept[slot as usize] = tile;
            self.entering.push(slot);
        }
        self.grass.set_square(square.extent().0);
        self.square = square;
        // Started now, so that the tile kernel poses them from their pose
        // in this frame even without a step.
        self.record_enter(rec);
        Ok(())
    }

    /// Records one step of the kept blades (the tiles that came in first
    /// start at their quasi-static pose), `end_time` the simulated time
    /// at its end.
    pub fn record_step(&mut self, rec: &Recording, end_time: f32) {
        self.record_enter(rec);
        self.grass.record_step(rec, 0, end_time);
    }

    /// The enter kernel over the entering slots' blades.
    fn record_enter(&mut self, rec: &Recording) {
        if self.entering.is_empty() {
            return;
        }
        self.entering.sort_unstable();
        let per_tile = self.square.per_tile;
        rec.bind_pipeline(&self.enter);
        rec.bind_set(&self.enter, &self.enter_set);
        // One dispatch a tile: each finds its blades' last poses by its
        // own coordinates.
        for &slot in &self.entering {
            let tile = self.kept[slot as usize];
            rec.uses(&self.enter_uses);
            let push = CoverEnterPush {
                grid: grid_params(&self.grid, self.grid.face_count() as u32),
                first: slot * per_tile,
                count: per_tile,
                far_first: cover::state_slot(tile, self.far_side) * per_tile,
                far_tag: if self.far_kept {
                    cover::far_tag(tile)
                } else {
                    0
                },
            };
            rec.push_constants(&self.enter, &push);
            rec.dispatch(per_tile.div_ceil(COVER_GROUP));
        }
        self.entering.clear();
    }

    /// The tile kernel's last pose of every cover blade, which a tile
    /// coming in starts from (for `CoverSetup::far_poses`); None where the
    /// device cannot bind them whole.
    pub fn far_poses(&self) -> Option<&Buffer> {
        self.far_kept.then_some(&self.far_poses)
    }

    /// The colliders from the next recorded step on (the viewer's ball).
    pub fn set_colliders(&mut self, colliders: &[Collider]) -> Result<()> {
        self.grass.set_colliders(colliders)
    }

    /// Each kept blade's pressed state in slot order, which the tile
    /// kernel poses from (None where made without colliders).
    pub fn presses(&self) -> Option<&Buffer> {
        self.grass.presses()
    }

    /// The wind grid's corner from the next step on (the wind window
    /// moved).
    pub fn set_wind_origin(&mut self, origin: glam::Vec3) {
        self.grid.origin = origin;
        self.grass.set_wind_origin(origin);
    }

    /// The kept blades' states in slot order (state slot x blades a tile
    /// + index), which the tile kernel poses from.
    pub fn states(&self) -> &Buffer {
        self.grass.states()
    }

    /// The tiles kept now.
    pub fn square(&self) -> &CoverTiles {
        &self.square
    }

    /// Blades stepped each step.
    pub fn blade_count(&self) -> u32 {
        self.grass.blade_count()
    }

    /// The dynamics' grass step (for tests).
    pub fn grass(&self) -> &GrassPass {
        &self.grass
    }
}

/// What a kept tile's blades are made from: the cover's seed as the tile
/// kernel takes it, the scene's shapes and physics ranges, the ground.
struct TileMaker {
    terrain: Terrain,
    seed: u32,
    shape: BladeShape,
    dynamics: GrassDynamics,
}

impl TileMaker {
    /// The `per_tile` blades of `tile` as the dynamics step them.
    fn blades(&self, tile: [i32; 2], per_tile: u32) -> Result<Vec<GrassBlade>> {
        (0..per_tile)
            .map(|index| {
                cover::grass_blade(
                    &self.terrain,
                    self.seed,
                    &self.shape,
                    &self.dynamics,
                    tile,
                    index,
                )
            })
            .collect()
    }
}

/// The tile kernel's last poses (`FarPose`) for the whole square of
/// `cover`'s tiles, cleared: no blade has been posed yet; and true. Where
/// one storage binding of the device cannot hold them (the Vulkan
/// minimum, 128 MiB, holds 2.8 million blades'), a one-pose placeholder
/// and false: the far field is then posed without them
/// (`far_poses_missing` says so).
pub fn far_poses_buffer(
    gpu: &Gpu,
    commands: &CommandPool,
    cover: &Cover,
) -> Result<(Buffer, bool)> {
    let pose = std::mem::size_of::<FarPose>() as u64;
    if far_poses_missing(gpu, cover).is_some() {
        let placeholder = Buffer::new(
            gpu,
            "cover last poses placeholder (the device cannot bind them whole)",
            pose,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        return Ok((placeholder, false));
    }
    let far_poses = Buffer::new(
        gpu,
        "cover blades' last poses (FarPose)",
        cover::most_blades(cover) * pose,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?;
    let rec = commands.begin()?;
    rec.fill_buffer(&far_poses, 0);
    rec.submit_and_wait("clearing the cover's last poses")?;
    Ok((far_poses, true))
}

/// Why the cover's far field cannot keep its blades' last poses on this
/// device (None: it can): the warning a render reports.
pub fn far_poses_missing(gpu: &Gpu, cover: &Cover) -> Option<String> {
    let most = cover::most_blades(cover);
    let bytes = most.saturating_mul(std::mem::size_of::<FarPose>() as u64);
    let range = gpu.limits().max_storage_buffer_range as u64;
    (bytes > range).then(|| {
        format!(
            "grass.cover: the last poses of {most} blades take {bytes} bytes, more than one storage binding of this device holds ({range}): far blades show their balance at once and may jump between frames; lower density or view_distance to keep them"
        )
    })
}
