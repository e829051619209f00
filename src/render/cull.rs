//! The cull pass (ours; after Jahrmann and Wimmer's compute culling): each
//! frame, after the grass step and before the shadow pass, GPU compute
//! tests every blade's current control points (glsl/common/cull.glsl; the
//! CPU reference is src/render/visibility.rs) and compacts the survivors
//! into two index lists, one for the colour pass (blades whose bounds
//! reach into the view and are not hidden behind the previous frame's
//! depth, src/render/depth_pyramid.rs) and one for the shadow pass (blades
//! whose shadow can fall into the view), each drawn by one indexed indirect
//! draw. The pipeline the survivors go through is the paper's, unchanged.
//!
//! Three kernels: flags (one invocation per blade, a count per
//! workgroup), scan (one workgroup: each workgroup's first slot, and the
//! draws) and compact (each survivor writes its indices at its slot). The
//! lists keep blade order, so the frames are the same every run.
//!
//! The pass binds the blade buffer, the frame uniforms and the depth
//! pyramid, which it does not own; its sets keep them alive.

use std::ops::Range;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::{
    Access, Bound, Buffer, BufferUse, DescriptorSet, Gpu, LayoutBinding, MemoryLocation, Pipeline,
    PipelineLayout, Recording,
};
use crate::interface::{CullPush, CULL_GROUP as GROUP};
use crate::render::depth_pyramid::Occluders;
use crate::shaders::Spirv;

/// Bytes of one blade's control points, the flag kernel's per-blade part.
const BLADE_BYTES: usize = 4 * std::mem::size_of::<crate::model::BladeVertex>();
/// Bytes of one `VkDrawIndexedIndirectCommand`.
const DRAW_BYTES: u64 = 20;
/// Words of the draws buffer: the colour draw, the shadow draw, the
/// blades tested, those the distance thinning left, those of them not
/// seen edge-on from the camera, and the blades in view the previous
/// frame's depth hides.
const DRAW_WORDS: usize = 15;

/// The cull kernels, in the order a frame runs them: the flags (per
/// batch of blades), the scan, the compaction.
const CULL_KERNELS: [&Spirv; 3] = [
    &crate::shaders::CULL_FLAGS_COMP,
    &crate::shaders::CULL_SCAN_COMP,
    &crate::shaders::CULL_COMPACT_COMP,
];

/// Set 0 of the cull kernels, as they use it (build.rs's reflection of
/// glsl/cull/*.comp): what binding b holds is `cull_bound`'s b-th.
pub fn cull_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&CULL_KERNELS, 0)
}

/// What the cull kernels' set binds for the batch `batch` of blades, in
/// binding order: the frame uniforms (camera, sun), the batch's control
/// points, one word of flags per blade, per workgroup the survivors then
/// first slots, the two indirect draws and the counts, the colour pass's
/// index list, the shadow pass's, per workgroup the blades occluded, the
/// depth pyramid (glsl/common/depth_pyramid.glsl).
fn cull_bound<'a>(
    frame_uniforms: &'a Buffer,
    blades: &'a Buffer,
    b: &'a CullBuffers,
    pyramid: &'a Buffer,
    batch: &Range<u32>,
) -> Vec<Bound<'a>> {
    vec![
        Bound::Buffer(frame_uniforms),
        crate::gpu::part(blades, batch, BLADE_BYTES),
        Bound::Buffer(&b.flags),
        Bound::Buffer(&b.groups),
        Bound::Buffer(&b.draws),
        Bound::Buffer(&b.color_list),
        Bound::Buffer(&b.shadow_list),
        Bound::Buffer(&b.groups_occluded),
        Bound::Buffer(pyramid),
    ]
}

/// Of the blades tested in the last frame, how many each pass drew.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CullCounts {
    /// Blades tested.
    pub blades: u32,
    /// Left by the distance thinning (all of them with it off).
    pub thinned_to: u32,
    /// Of those, not seen edge-on from the camera (all of them with the
    /// orientation test off).
    pub face_camera: u32,
    /// Drawn by the colour pass: their bounds reach into the view, and
    /// the previous frame's depth does not hide them.
    pub in_view: u32,
    /// In view, but hidden behind the previous frame's depth: not drawn
    /// (0 with occlusion culling off, and in a frame with no frame before).
    pub occluded: u32,
    /// Drawn by the shadow pass: their shadow can fall into the view
    /// (all of them when the sun is too low to bound it; none when
    /// shadows are off).
    pub shadow_casters: u32,
    /// Their shadow could fall into the view, but only where the previous
    /// frame's depth hides every receiver: not drawn (0 with occlusion
    /// culling off, and in a frame with no frame before).
    pub casters_occluded: u32,
}

/// What a pass draws of the blade buffer: every blade, or a cull pass's
/// list.
#[derive(Clone, Copy)]
pub enum BladeDraw<'a> {
    All(u32),
    Listed(BladeList<'a>),
}

impl BladeDraw<'_> {
    /// Records the draw of `blades`' 4-point patches, with the blade
    /// pipeline and its set bound.
    pub fn record(self, rec: &Recording, blades: &Buffer) {
        rec.bind_vertex_buffer(blades);
        match self {
            BladeDraw::All(count) => rec.draw(count * 4),
            BladeDraw::Listed(list) => {
                rec.bind_index_buffer(list.indices);
                rec.draw_indexed_indirect(list.draws, list.offset);
            }
        }
    }
}

/// A list of blades a pass draws: its index buffer and the draw the cull
/// pass wrote for it.
#[derive(Clone, Copy)]
pub struct BladeList<'a> {
    pub indices: &'a Buffer,
    pub draws: &'a Buffer,
    /// Byte offset of the list's `VkDrawIndexedIndirectCommand` in `draws`.
    pub offset: u64,
}

pub struct CullPass {
    // The flag kernel reads the control points a batch of blades at a time
    // (`gpu::batches`: a million blades are more than lavapipe lets one
    // binding reach), one set per batch; the scan and the compaction,
    // which do not read them, use the first.
    batches: Vec<(DescriptorSet, Range<u32>)>,
    flags_kernel: Pipeline,
    scan_kernel: Pipeline,
    compact_kernel: Pipeline,
    buffers: CullBuffers,
    push: CullPush,
    /// What each kernel (`CULL_KERNELS`) does to what its set binds, from
    /// build.rs's reflection: the flag kernel's over every batch (each
    /// binds a part of the same control points).
    kernel_uses: [Vec<BufferUse>; 3],
}

impl CullPass {
    /// The pass over `blade_count` blades of `blades` (4 control points
    /// each), seen as `frame_uniforms` says; shadow casters are listed
    /// only with `shadows`; blades seen edge-on closer than the cosine
    /// `edge_on` are left out (1: none); with a depth `pyramid`'s buffer,
    /// blades hidden behind it are left out of the colour list.
    pub fn new(
        gpu: &Gpu,
        frame_uniforms: &Buffer,
        blades: &Buffer,
        blade_count: u32,
        shadows: bool,
        edge_on: f32,
        pyramid: Option<&Buffer>,
    ) -> Result<Self> {
        if blade_count == 0 || blade_count > u32::MAX / 4 {
            return Err(Error::InvalidInput(format!(
                "{blade_count} blades cannot be culled"
            )));
        }
        let groups = blade_count.div_ceil(GROUP);
        let b = CullBuffers::new(gpu, blade_count, groups, shadows, pyramid.is_none())?;
        let pyramid = pyramid.or(b.no_pyramid.as_ref()).expect("one of the two");
        let layout = PipelineLayout::new::<CullPush>(
            gpu,
            &cull_set(),
            vk::ShaderStageFlags::COMPUTE,
            "cull",
        )?;
        let [flags_kernel, scan_kernel, compact_kernel] =
            CULL_KERNELS.map(|kernel| Pipeline::compute(gpu, &layout, kernel));
        let batches = crate::gpu::sets_per_batch(
            gpu,
            &layout,
            &cull_set(),
            blade_count,
            BLADE_BYTES as u64,
            "cull descriptor set",
            |batch| cull_bound(frame_uniforms, blades, &b, pyramid, batch),
        )?;
        let first_batch = batches.first().map_or(0..0, |(_, range)| range.clone());
        let first = cull_bound(frame_uniforms, blades, &b, pyramid, &first_batch);
        let kernel_uses = CULL_KERNELS.map(|kernel| kernel.buffer_uses(0, &first));
        Ok(Self {
            batches,
            flags_kernel: flags_kernel?,
            scan_kernel: scan_kernel?,
            compact_kernel: compact_kernel?,
            kernel_uses,
            buffers: b,
            push: CullPush {
                blade_count,
                flag_groups: groups,
                shadows: shadows as u32,
                edge_on,
                pyramid_width: 1,
                pyramid_height: 1,
                pyramid_levels: 1,
                pyramid_holds: 0,
                ..CullPush::default()
            },
        })
    }

    /// Records the three kernels, testing the blades in view against
    /// `occluders` (None: none is occluded). Waits for the grass step's
    /// writes (and the blades' upload), the previous frame's pyramid, and
    /// the previous frame's draws to finish reading the lists; ends with
    /// the lists and draws visible to the draws and the host.
    pub fn record(&self, rec: &Recording, occluders: Option<Occluders>) {
        let mut push = self.push;
        if let Some(o) = occluders {
            push.seen_from = o.seen_from.to_cols_array_2d();
            push.pyramid_width = o.width;
            push.pyramid_height = o.height;
            push.pyramid_levels = o.levels;
            push.pyramid_holds = 1;
        }
        // The batches write their own blades' flags and workgroups' counts:
        // declared once for all of them.
        rec.uses(&self.kernel_uses[0]);
        rec.bind_pipeline(&self.flags_kernel);
        for (set, blades) in &self.batches {
            push.first_blade = blades.start;
            rec.bind_set(&self.flags_kernel, set);
            rec.push_constants(&self.flags_kernel, &push);
            rec.dispatch((blades.len() as u32).div_ceil(GROUP));
        }
        let first_set = &self.batches[0].0;
        for (kernel, dispatch, uses) in [
            (&self.scan_kernel, 1, &self.kernel_uses[1]),
            (
                &self.compact_kernel,
                self.push.flag_groups,
                &self.kernel_uses[2],
            ),
        ] {
            rec.uses(uses);
            rec.bind_pipeline(kernel);
            rec.bind_set(kernel, first_set);
            rec.push_constants(kernel, &push);
            rec.dispatch(dispatch);
        }
    }

    /// What drawing the lists does to this pass's results: the lists read
    /// as indices, the draws as indirect parameters, and the counts by the
    /// host after the frame (`counts`). The frame declares them before the
    /// draws.
    pub fn drawn_uses(&self) -> [BufferUse; 3] {
        [
            BufferUse::new(&self.buffers.color_list, Access::INDEX_INPUT),
            BufferUse::new(&self.buffers.shadow_list, Access::INDEX_INPUT),
            BufferUse::new(
                &self.buffers.draws,
                Access::DRAW_INDIRECT.and(Access::HOST_READ),
            ),
        ]
    }

    /// The colour pass's blades.
    pub fn color_list(&self) -> BladeList<'_> {
        BladeList {
            indices: &self.buffers.color_list,
            draws: &self.buffers.draws,
            offset: 0,
        }
    }

    /// The shadow pass's blades.
    pub fn shadow_list(&self) -> BladeList<'_> {
        BladeList {
            indices: &self.buffers.shadow_list,
            draws: &self.buffers.draws,
            offset: DRAW_BYTES,
        }
    }

    /// The counts of the last frame recorded and waited for.
    pub fn counts(&self) -> CullCounts {
        let words: &[u32] = bytemuck::cast_slice(
            &self
                .buffers
                .draws
                .mapped()
                .expect("the draws buffer is host-visible")[..4 * DRAW_WORDS],
        );
        CullCounts {
            blades: words[10],
            thinned_to: words[11],
            face_camera: words[12],
            in_view: words[0] / 4,
            occluded: words[13],
            shadow_casters: words[5] / 4,
            casters_occluded: words[14],
        }
    }

    /// The colour list of the last frame (blade indices, in order), for
    /// tests: read back from the device.
    pub fn read_color_list(
        &self,
        gpu: &Gpu,
        commands: &crate::gpu::CommandPool,
    ) -> Result<Vec<u32>> {
        let n = self.counts().in_view as usize;
        read_list(gpu, commands, &self.buffers.color_list, n)
    }

    /// The shadow list of the last frame, as `read_color_list`.
    pub fn read_shadow_list(
        &self,
        gpu: &Gpu,
        commands: &crate::gpu::CommandPool,
    ) -> Result<Vec<u32>> {
        let n = self.counts().shadow_casters as usize;
        read_list(gpu, commands, &self.buffers.shadow_list, n)
    }
}

/// The blades of a list: every fourth index over 4.
fn read_list(
    gpu: &Gpu,
    commands: &crate::gpu::CommandPool,
    list: &Buffer,
    blades: usize,
) -> Result<Vec<u32>> {
    if blades == 0 {
        return Ok(Vec::new());
    }
    let indices: Vec<[u32; 4]> = list.read_back(gpu, commands, blades)?;
    Ok(indices.iter().map(|q| q[0] / 4).collect())
}

/// Device memory the cull pass needs for `blades` blades: flags, two
/// lists of four indices, five counts per workgroup.
pub fn device_bytes(blades: usize) -> u64 {
    blades as u64 * (4 + 16 + 16) + 20 * (blades as u64).div_ceil(GROUP as u64)
}

/// The cull pass's own buffers: each blade's flags, each workgroup's
/// counts (and of occluded blades): between the three kernels; the
/// indirect draws and the count tested, host-visible so each frame's
/// counts can be read after it; the two lists; and a placeholder bound
/// for the pyramid without occlusion culling.
struct CullBuffers {
    flags: Buffer,
    groups: Buffer,
    groups_occluded: Buffer,
    draws: Buffer,
    color_list: Buffer,
    shadow_list: Buffer,
    no_pyramid: Option<Buffer>,
}

impl CullBuffers {
    fn new(
        gpu: &Gpu,
        blade_count: u32,
        groups: u32,
        shadows: bool,
        no_pyramid: bool,
    ) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let buffer = |name: &str, bytes: u64, usage: vk::BufferUsageFlags| {
            Buffer::new(gpu, name, bytes, storage | usage, MemoryLocation::GpuOnly)
        };
        let none = vk::BufferUsageFlags::empty();
        let lists = vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        Ok(Self {
            flags: buffer(
                "cull flags (one word per blade)",
                4 * blade_count as u64,
                none,
            )?,
            groups: buffer(
                "cull workgroup counts and first slots",
                16 * groups as u64,
                none,
            )?,
            groups_occluded: buffer(
                "cull workgroup counts of occluded blades and casters",
                8 * groups as u64,
                none,
            )?,
            no_pyramid: match no_pyramid {
                true => Some(buffer(
                    "cull depth pyramid (unused: no occlusion culling)",
                    16,
                    none,
                )?),
                false => None,
            },
            draws: Buffer::new(
                gpu,
                "cull indirect draws (colour, shadow) and count",
                4 * DRAW_WORDS as u64,
                storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
                MemoryLocation::GpuToCpu,
            )?,
            color_list: buffer(
                "cull colour-pass blade list (index buffer)",
                16 * blade_count as u64,
                lists,
            )?,
            // Without shadows the shadow list is never written or drawn; it
            // still has to be bound.
            shadow_list: if shadows {
                buffer(
                    "cull shadow-pass blade list (index buffer)",
                    16 * blade_count as u64,
                    lists,
                )?
            } else {
                buffer(
                    "cull shadow-pass blade list (unused: no shadows)",
                    16,
                    vk::BufferUsageFlags::INDEX_BUFFER,
                )?
            },
        })
    }
}
