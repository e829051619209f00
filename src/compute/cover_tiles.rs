//! The cover's tile pass (glsl/cover/tiles.comp; `[grass.cover]`): makes
//! the blades of the tiles around the camera in the blade buffer, from the
//! cover's seed and each tile's coordinates, as `scene::cover` does on the
//! CPU. The blades are made afresh each time the pass is recorded, so a
//! tile that comes back holds the same blades; what is kept between
//! frames is each posed blade's last pose (`FarPose`), which its
//! quasi-static pose goes on from without jumping.

use std::ops::Range;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::batches::{part, sets_per_batch};
use crate::gpu::{
    Access, Buffer, BufferUse, DescriptorSet, Gpu, LayoutBinding, Pipeline, PipelineLayout,
    Recording,
};
use crate::gpu::{Bound, CommandPool, MemoryLocation};
use crate::interface::{CoverParams, CoverPush, COVER_GROUP};
use crate::model::terrain::Terrain;
use crate::model::wind::WindGrid;
use crate::model::BladeVertex;
use crate::scene::cover::{self, CoverTiles};
use crate::scene::{Cover, Grass};
use crate::shaders::Spirv;

/// The tile kernel.
const COVER_KERNEL: &Spirv = &crate::shaders::COVER_TILES_COMP;

/// Set 0 of the tile kernel, as it uses it (build.rs's reflection): what
/// binding b holds is `tile_bound`'s b-th.
pub fn cover_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&[COVER_KERNEL], 0)
}

/// The wind the cover's blades are posed in: the solver's velocity (one
/// copy of every face) and its grid.
pub struct CoverWind<'a> {
    pub velocity: &'a Buffer,
    pub grid: WindGrid,
}

/// What the tile pass is made for.
pub struct CoverSetup<'a> {
    pub cover: &'a Cover,
    /// The cover's seed: its own or the scene's.
    pub seed: u64,
    /// The scene's blade shapes and physics ranges.
    pub grass: &'a Grass,
    /// The blade buffer, holding `cover::most_blades(cover)` blades from
    /// blade `base` on (after the scene's patches' blades).
    pub vertices: &'a Buffer,
    pub base: u32,
    /// With a wind the blades take their quasi-static pose in it;
    /// without, they stand at rest.
    pub wind: Option<CoverWind<'a>>,
    /// The frame uniforms (the renderer's uniform buffer): what the frame
    /// draws, for `pose_drawn_only`.
    pub frame: &'a Buffer,
    /// Pose only the blades the frame may draw (the others keep their
    /// rest shape, which no pass draws either).
    pub pose_drawn_only: bool,
    /// The states of the blades the paper's dynamics step near the camera
    /// (`CoverDynamics::states`; None: every blade quasi-static).
    pub states: Option<&'a Buffer>,
    /// Their pressed states (`CoverDynamics::presses`, made with
    /// colliders; None: none kept).
    pub presses: Option<&'a Buffer>,
    /// The ground the blades are rooted on.
    pub terrain: &'a Terrain,
    /// Where the pass keeps each blade's last pose (`FarPose`):
    /// `CoverDynamics::far_poses`, whose tiles coming in start from it
    /// (None: the pass keeps its own).
    pub far_poses: Option<&'a Buffer>,
}

/// One blade's control points in the blade buffer.
const BLADE_BYTES: usize = 4 * std::mem::size_of::<BladeVertex>();

pub struct CoverTilePass {
    pipeline: Pipeline,
    /// `record`, written into the command buffer before each pass (the
    /// wind window moves).
    params: Buffer,
    record: CoverParams,
    /// How many blades the last recorded pass posed (host-visible).
    posed: Buffer,
    /// Whether the blades are posed in a wind (else a placeholder is bound
    /// in its place), and whether the kept blades' states are
    /// (`CoverDynamics`).
    has_wind: bool,
    has_states: bool,
    /// What the kernel does to what its sets bind (build.rs's reflection):
    /// declared once for every batch (each binds a part of the same blade
    /// buffer).
    kernel_uses: Vec<BufferUse>,
    _placeholder: Option<Buffer>,
    /// Each blade's pose the frame before, in its tile's slot of the
    /// square (`cover::state_slot`): what its quasi-static pose goes on
    /// from (`CoverDynamics::far_poses`, or the pass's own without
    /// dynamics, or a placeholder where the device cannot bind them whole:
    /// `CoverParams::far_kept` 0). Cleared: no blade has a past at first.
    _own_far_poses: Option<Buffer>,
    /// One set per batch of the blade buffer, with its blades.
    sets: Vec<(DescriptorSet, Range<u32>)>,
    /// The buffer's blade the cover starts at, and how many blades it
    /// holds for it: `cover::most_blades`.
    base: u32,
    capacity: u32,
    seed: u32,
    kinds: [f32; 3],
    height: [f32; 2],
    width: [f32; 2],
    /// Workgroups one dispatch may have (maxComputeWorkGroupCount[0]).
    max_groups: u32,
}

/// The most blades the cover may hold (`cover::most_blades`) and the end
/// of its part of the blade buffer, after the patches' `base`: refused
/// where one buffer cannot index them or `vertices` cannot hold them.
fn room_for(cover: &Cover, base: u32, vertices: &Buffer) -> Result<(u32, u32)> {
    let most = cover::most_blades(cover);
    let too_many = || {
        Error::InvalidInput(format!(
            "grass.cover: {most} blades around the camera after {base} of the patches' are more than one buffer indexes; lower density or view_distance"
        ))
    };
    let capacity = u32::try_from(most).map_err(|_| too_many())?;
    let end = base.checked_add(capacity).ok_or_else(too_many)?;
    if vertices.size < end as u64 * BLADE_BYTES as u64 {
        return Err(Error::InvalidInput(format!(
            "the blade buffer holds {} bytes, the patches' {base} and the cover's {most} blades need {}",
            vertices.size,
            end as u64 * BLADE_BYTES as u64
        )));
    }
    Ok((capacity, end))
}

/// What the kernel reads of the scene: the blades' physics ranges, the
/// simulated radius, the ground's steepest slope; the wind and what the
/// pass is given left at zero.
fn params_of(cover: &Cover, grass: &Grass, terrain: &Terrain) -> CoverParams {
    let d = &grass.dynamics;
    CoverParams {
        tip_stiffness: d.tip_stiffness,
        stiffness_ratio: d.stiffness_ratio,
        sigma: d.sigma,
        simulate_radius: cover.simulate_radius(),
        edge_mass: d.edge_mass,
        far_tracking: 1,
        max_slope: terrain.max_slope(),
        ..bytemuck::Zeroable::zeroed()
    }
}

/// One set per batch of the blade buffer holding some of the cover's
/// blades (`cover`: where they lie in it): binding 0 the frame, 1 the
/// batch's blades, 2 to 8 `rest` in order. The batches run over the whole
/// buffer, so that each binding starts at an offset every device's
/// alignment divides; the kernel writes only the cover's part.
fn tile_sets(
    gpu: &Gpu,
    layout: &PipelineLayout,
    vertices: &Buffer,
    cover: Range<u32>,
    frame: &Buffer,
    rest: [&Buffer; 7],
) -> Result<Vec<(DescriptorSet, Range<u32>)>> {
    let sets = sets_per_batch(
        gpu,
        layout,
        &cover_set(),
        cover.end,
        BLADE_BYTES as u64,
        "cover tiles set",
        |blades| tile_bound(frame, vertices, blades, rest),
    )?;
    Ok(sets
        .into_iter()
        .filter(|(_, blades)| blades.end > cover.start)
        .collect())
}

/// What the tile kernel's set binds for the batch `blades` of the blade
/// buffer, in binding order: the frame uniforms (camera, sun, thinning),
/// the batch's control points, then `rest`: `CoverParams`, the wind
/// velocity (or a placeholder), the blades posed and left out (three
/// words, host-read), the kept blades' states (or a placeholder), the
/// terrain (`TerrainHeader` and its words), the kept blades' pressed
/// states (or a placeholder), each blade's pose the frame before
/// (`FarPose`).
fn tile_bound<'a>(
    frame: &'a Buffer,
    vertices: &'a Buffer,
    blades: &Range<u32>,
    rest: [&'a Buffer; 7],
) -> Vec<Bound<'a>> {
    let mut bound = vec![Bound::Buffer(frame), part(vertices, blades, BLADE_BYTES)];
    bound.extend(rest.iter().map(|&b| Bound::Buffer(b)));
    bound
}

/// One buffer standing for the wind, the states and the pressed states
/// where any of `optional` is missing (the kernel reads none of those
/// then).
fn placeholder_for(gpu: &Gpu, optional: &[Option<&Buffer>; 3]) -> Result<Option<Buffer>> {
    if optional.iter().all(Option::is_some) {
        return Ok(None);
    }
    Buffer::new(
        gpu,
        "cover placeholder (no wind: blades at rest; no dynamics; no pressed states)",
        32,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .map(Some)
}

/// The kernel's counters, read by the host: the blades posed
/// quasi-statically and from their state, those left out, and the
/// largest tip moves.
fn posed_counters(gpu: &Gpu) -> Result<Buffer> {
    Buffer::new(
        gpu,
        "cover blades posed (quasi-static, from their state), left out, and the largest tip moves",
        20,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )
}

/// The buffers the pass makes for itself: its parameters (and the record
/// they were written from), the ground's heights, the counters the host
/// reads, and the last poses where the dynamics keep none.
struct TileBuffers {
    record: CoverParams,
    params: Buffer,
    terrain: Buffer,
    posed: Buffer,
    far_poses: Option<Buffer>,
}

impl TileBuffers {
    fn new(gpu: &Gpu, commands: &CommandPool, setup: &CoverSetup, pressed: bool) -> Result<Self> {
        let cover = setup.cover;
        // The last poses: the dynamics' (whose tiles coming in start
        // from them), else the pass's own; none where the device cannot
        // bind them whole (a placeholder of its own: the kernel's binding
        // is read and written).
        let (far_poses, far_kept) = match setup.far_poses {
            Some(_) => (None, true),
            None => super::cover_dynamics::far_poses_buffer(gpu, commands, cover)
                .map(|(own, kept)| (Some(own), kept))?,
        };
        let record = CoverParams {
            grid: match &setup.wind {
                Some(w) => super::wind_pass::grid_params(&w.grid, w.grid.face_count() as u32),
                None => bytemuck::Zeroable::zeroed(),
            },
            pose: setup.wind.is_some() as u32,
            pose_drawn_only: setup.pose_drawn_only as u32,
            pressed_states: pressed as u32,
            far_kept: far_kept as u32,
            ..params_of(cover, setup.grass, setup.terrain)
        };
        let params = Buffer::with_data(
            gpu,
            commands,
            "cover tile parameters",
            bytemuck::bytes_of(&record),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            Access::COMPUTE_READ,
        )?;
        let terrain = super::terrain_buffer(
            gpu,
            commands,
            setup.terrain,
            "cover terrain (height map, hills, ridges)",
        )?;
        Ok(Self {
            record,
            params,
            terrain,
            posed: posed_counters(gpu)?,
            far_poses,
        })
    }
}

impl CoverTilePass {
    /// The pass `setup` describes.
    pub fn new(gpu: &Gpu, commands: &CommandPool, setup: CoverSetup<'_>) -> Result<Self> {
        let CoverSetup {
            cover,
            grass,
            vertices,
            base,
            states,
            ..
        } = setup;
        let wind = setup.wind.as_ref();
        let presses = setup.presses.filter(|_| states.is_some());
        let (capacity, end) = room_for(cover, base, vertices)?;
        let own = TileBuffers::new(gpu, commands, &setup, presses.is_some())?;
        let far_poses = setup
            .far_poses
            .or(own.far_poses.as_ref())
            .expect("the dynamics' or the pass's own");
        // One placeholder stands for the wind, the states and the pressed
        // states where any is missing (the kernel reads none of those then).
        let optional = [wind.map(|w| w.velocity), states, presses];
        let placeholder = placeholder_for(gpu, &optional)?;
        let [wind_buffer, states_buffer, presses_buffer] =
            optional.map(|given| given.or(placeholder.as_ref()).expect("a placeholder"));
        let layout = PipelineLayout::new::<CoverPush>(
            gpu,
            &cover_set(),
            vk::ShaderStageFlags::COMPUTE,
            "cover tiles",
        )?;
        let pipeline = Pipeline::compute(gpu, &layout, COVER_KERNEL)?;
        let rest = [
            &own.params,
            wind_buffer,
            &own.posed,
            states_buffer,
            &own.terrain,
            presses_buffer,
            far_poses,
        ];
        let sets = tile_sets(gpu, &layout, vertices, base..end, setup.frame, rest)?;
        let first = sets.first().map_or(0..0, |(_, blades)| blades.clone());
        let kernel_uses =
            COVER_KERNEL.buffer_uses(0, &tile_bound(setup.frame, vertices, &first, rest));
        Ok(Self {
            pipeline,
            params: own.params,
            record: own.record,
            posed: own.posed,
            has_wind: wind.is_some(),
            has_states: states.is_some(),
            kernel_uses,
            _placeholder: placeholder,
            _own_far_poses: own.far_poses,
            sets,
            base,
            capacity,
            seed: cover::seed32(setup.seed),
            kinds: cover::kind_thresholds(&grass.shape),
            height: grass.shape.height,
            width: grass.shape.width,
            max_groups: gpu.limits().max_compute_work_group_count[0].max(1),
        })
    }

    /// The wind grid the blades are posed in from the next pass on (the
    /// wind window moved under the camera); ignored without a wind.
    pub fn set_wind_grid(&mut self, grid: &WindGrid) {
        if self.has_wind {
            self.record.grid = super::wind_pass::grid_params(grid, grid.face_count() as u32);
        }
    }

    /// The tiles whose blades' states the next pass poses
    /// (`CoverDynamics::square`) around a camera at `camera` (x, z); None:
    /// every blade quasi-static. Ignored by a pass made without states.
    pub fn set_dynamics(&mut self, kept: Option<&CoverTiles>, camera: glam::Vec2) {
        let r = &mut self.record;
        r.eye = camera.to_array();
        match kept.filter(|_| self.has_states) {
            Some(k) => {
                r.kept_origin = k.origin;
                r.kept_side = k.side;
                r.dynamic = 1;
            }
            None => r.dynamic = 0,
        }
    }

    /// Simulated seconds between the last recorded pass and the next:
    /// how far a blade posed in both goes towards its new balance.
    pub fn set_elapsed(&mut self, seconds: f32) {
        self.record.elapsed = seconds;
    }

    /// false: every blade shows its balance at once, as if it had no past
    /// (what the far field did before its poses were kept; for measuring
    /// the difference).
    pub fn set_far_tracking(&mut self, on: bool) {
        self.record.far_tracking = on as u32;
    }

    /// The buffer's blade the cover's first blade is.
    pub fn base(&self) -> u32 {
        self.base
    }

    /// Records the making of `tiles`' blades (`CoverTiles::around` the
    /// camera) into the blade buffer the pass was made for, declaring its
    /// write.
    pub fn record(&self, rec: &Recording, tiles: &CoverTiles) -> Result<()> {
        let blades = tiles.blade_count();
        if blades > self.capacity as u64 {
            return Err(Error::InvalidInput(format!(
                "{blades} cover blades do not fit the {} the blade buffer holds",
                self.capacity
            )));
        }
        let end = self.base + blades as u32;
        rec.fill_buffer(&self.posed, 0);
        rec.update_buffer(&self.params, 0, bytemuck::cast_slice(&[self.record]));
        rec.uses(&self.kernel_uses);
        rec.bind_pipeline(&self.pipeline);
        let per_dispatch = self.max_groups.saturating_mul(COVER_GROUP);
        for (set, range) in &self.sets {
            let (from, to) = (range.start.max(self.base), range.end.min(end));
            if from >= to {
                continue;
            }
            rec.bind_set(&self.pipeline, set);
            let mut start = from - range.start;
            while range.start + start < to {
                let count = (to - range.start - start).min(per_dispatch);
                let push = CoverPush {
                    origin: tiles.origin,
                    side: tiles.side,
                    per_tile: tiles.per_tile,
                    first: range.start,
                    start,
                    count,
                    seed: self.seed,
                    kinds: self.kinds,
                    tile_m: cover::TILE_M,
                    height: self.height,
                    width: self.width,
                    base: self.base,
                    _pad0: 0,
                    _pad1: 0,
                    _pad2: 0,
                    bounds_min: [tiles.bounds[0], tiles.bounds[1]],
                    bounds_max: [tiles.bounds[2], tiles.bounds[3]],
                };
                rec.push_constants(&self.pipeline, &push);
                rec.dispatch(count.div_ceil(COVER_GROUP));
                start += count;
            }
        }
        rec.uses(&[BufferUse::new(&self.posed, Access::HOST_READ)]);
        Ok(())
    }

    /// How many blades the last recorded pass, run and waited for, posed
    /// quasi-statically (the others stand at rest or take their dynamics'
    /// state).
    pub fn posed(&self) -> u32 {
        self.counter(0)
    }

    /// How many blades the last pass, run and waited for, posed from their
    /// dynamics' state (the simulated square's tiles).
    pub fn from_state(&self) -> u32 {
        self.counter(1)
    }

    /// How many blades the last pass, run and waited for, left out: rooted
    /// beyond the cover's bounds.
    pub fn outside(&self) -> u32 {
        self.counter(2)
    }

    /// The largest distance (m) a tip posed by both the last pass, run and
    /// waited for, and the one before it moved between them: over the
    /// blades posed quasi-statically, and over all.
    pub fn tip_jumps(&self) -> (f32, f32) {
        (
            f32::from_bits(self.counter(3)),
            f32::from_bits(self.counter(4)),
        )
    }

    fn counter(&self, word: usize) -> u32 {
        let bytes = self.posed.mapped().expect("the counts are host-visible");
        let at = 4 * word;
        u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
    }
}
