//! The depth pyramid (ours; the occlusion test of Jahrmann and Wimmer's
//! compute culling): after the colour pass, GPU compute reduces the frame's
//! depth into a pyramid whose every texel holds the farthest depth of what
//! it covers (glsl/cull/pyramid_*.comp, glsl/common/depth_pyramid.glsl).
//! The next frame's cull pass leaves out a blade in view whose bounds lie
//! behind every texel under them (glsl/cull/flags.comp).
//!
//! Level 0 has one texel per pixel (the farthest of its samples); each
//! level above is half the one below, rounded up, down to 1 x 1. All
//! levels lie one after another in one storage buffer.
//!
//! The pyramid remembers which camera saw the frame it holds, and holds
//! nothing until a frame that built it has finished: after a failed
//! submission, a jump ahead in simulated time (`forget`) or a resize (a new
//! pyramid), no blade is left out for occlusion until the next frame.

use ash::vk;
use glam::Mat4;

use crate::error::{Error, Result};
use crate::gpu::{
    Bound, Buffer, DescriptorSet, Gpu, Image, LayoutBinding, MemoryLocation, Pipeline,
    PipelineLayout, Recording,
};
use crate::shaders::{self, Spirv};

pub use crate::interface::PyramidLevel as Level;
use crate::interface::{PyramidPush, PYRAMID_TILE as TILE};

/// The pyramid's kernels: the base from single-sampled depth, the base
/// from multisampled depth (one of the two per pyramid), the reduction.
pub const PYRAMID_KERNELS: [&Spirv; 3] = [
    &shaders::CULL_PYRAMID_BASE_COMP,
    &shaders::CULL_PYRAMID_BASE_MULTISAMPLED_COMP,
    &shaders::CULL_PYRAMID_REDUCE_COMP,
];

/// Set 0 of the pyramid kernels, as their SPIR-V declares it: the colour
/// pass's depth, read by texel, and every level of the pyramid.
pub fn pyramid_set() -> Vec<LayoutBinding> {
    crate::gpu::kernels_set(&PYRAMID_KERNELS, 0)
}

/// The levels of the pyramid over a `width` x `height` depth image, as
/// glsl/common/depth_pyramid.glsl places them.
pub fn levels(width: u32, height: u32) -> Vec<Level> {
    let mut levels = vec![Level {
        offset: 0,
        width,
        height,
    }];
    while let Some(&below) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
        levels.push(Level {
            offset: below.offset + below.width * below.height,
            width: below.width.div_ceil(2),
            height: below.height.div_ceil(2),
        });
    }
    levels
}

/// What the cull pass needs of the pyramid to test a frame's blades
/// against it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occluders {
    /// World to clip space of the frame the pyramid holds.
    pub seen_from: Mat4,
    pub width: u32,
    pub height: u32,
    pub levels: u32,
}

pub struct DepthPyramid {
    set: DescriptorSet,
    /// The base kernel's SPIR-V, whose reflected accesses its dispatch
    /// declares (`record_build`).
    base: &'static Spirv,
    base_kernel: Pipeline,
    reduce_kernel: Pipeline,
    buffer: Buffer,
    levels: Vec<Level>,
    /// The camera of the finished frame the pyramid holds; None before one.
    holds: Option<Mat4>,
    /// The camera of the frame being recorded, held from `begin_frame`
    /// until `end_frame` says whether it finished.
    building: Option<Mat4>,
}

impl DepthPyramid {
    /// A pyramid over `depth`, the colour pass's depth target (made with
    /// SAMPLED usage).
    pub fn new(gpu: &Gpu, depth: &Image) -> Result<Self> {
        let samples = depth.samples;
        if !gpu
            .limits()
            .sampled_image_depth_sample_counts
            .contains(samples)
        {
            return Err(Error::InvalidInput(format!(
                "occlusion culling reads the depth image at {}x MSAA, which this device cannot sample; set occlusion = false in the scene's [cull] or lower --msaa",
                samples.as_raw()
            )));
        }
        let extent = depth.extent;
        let levels = levels(extent.width, extent.height);
        let buffer = Buffer::new(
            gpu,
            "depth pyramid (every level, farthest depth per texel)",
            bytes(&levels),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let set_layout = pyramid_set();
        let layout = PipelineLayout::new::<PyramidPush>(
            gpu,
            &set_layout,
            vk::ShaderStageFlags::COMPUTE,
            "depth pyramid",
        )?;
        let [single, multisampled, reduce] = PYRAMID_KERNELS;
        let base = if samples == vk::SampleCountFlags::TYPE_1 {
            single
        } else {
            multisampled
        };
        let base_kernel = Pipeline::compute(gpu, &layout, base)?;
        let reduce_kernel = Pipeline::compute(gpu, &layout, reduce)?;
        let set = DescriptorSet::new(
            gpu,
            &layout,
            &set_layout,
            &[Bound::Image(depth), Bound::Buffer(&buffer)],
            "depth pyramid descriptor set",
        )?;
        Ok(Self {
            set,
            base,
            base_kernel,
            reduce_kernel,
            buffer,
            levels,
            holds: None,
            building: None,
        })
    }

    /// The pyramid's buffer, which the cull pass binds.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// What a frame recorded now tests its blades against (None: nothing
    /// is left out for occlusion), and that frame's camera, `seen_from`,
    /// is what the pyramid will hold once it has finished.
    pub fn begin_frame(&mut self, seen_from: Mat4) -> Option<Occluders> {
        self.building = Some(seen_from);
        self.occluders()
    }

    /// What the pyramid holds now, as the cull pass reads it.
    pub fn occluders(&self) -> Option<Occluders> {
        let base = self.levels[0];
        self.holds.map(|seen_from| Occluders {
            seen_from,
            width: base.width,
            height: base.height,
            levels: self.levels.len() as u32,
        })
    }

    /// The frame begun last has finished (`finished`: its depth is in the
    /// pyramid) or failed (what the pyramid holds is unknown).
    pub fn end_frame(&mut self, finished: bool) {
        let built = self.building.take();
        self.holds = if finished { built } else { None };
    }

    /// The frame the pyramid holds no longer stands for the next one (the
    /// simulation jumped ahead).
    pub fn forget(&mut self) {
        self.holds = None;
    }

    /// Records the pyramid's build from `depth` (the colour pass's depth
    /// target, the one `new` was given): each kernel declares what its
    /// SPIR-V reads and writes of what the set binds, so the base waits
    /// for the colour pass's depth writes and runs after this frame's cull
    /// pass has read the previous pyramid (which the next frame's cull
    /// pass declares reading), each reduction after the level below.
    /// Leaves `depth` in the compute-sampled layout.
    pub fn record_build(&self, rec: &Recording, depth: &Image) {
        let [_, _, reduce] = PYRAMID_KERNELS;
        let bound = [Bound::Image(depth), Bound::Buffer(&self.buffer)];
        rec.declare(
            &self.base.buffer_uses(0, &bound),
            &self.base.image_uses(0, &bound),
        );
        let base = self.levels[0];
        // The base kernel reads only the level it writes: the depth image's size.
        let push = PyramidPush {
            below: Level::default(),
            level: base,
        };
        rec.bind_pipeline(&self.base_kernel);
        rec.bind_set(&self.base_kernel, &self.set);
        rec.push_constants(&self.base_kernel, &push);
        rec.dispatch_2d(base.width.div_ceil(TILE), base.height.div_ceil(TILE));
        rec.bind_pipeline(&self.reduce_kernel);
        rec.bind_set(&self.reduce_kernel, &self.set);
        let reduce_uses = reduce.buffer_uses(0, &bound);
        for pair in self.levels.windows(2) {
            let [below, level] = [pair[0], pair[1]];
            rec.uses(&reduce_uses);
            let push = PyramidPush { below, level };
            rec.push_constants(&self.reduce_kernel, &push);
            rec.dispatch_2d(level.width.div_ceil(TILE), level.height.div_ceil(TILE));
        }
    }
}

/// Device memory of a pyramid over a `width` x `height` frame.
pub fn device_bytes(width: u32, height: u32) -> u64 {
    bytes(&levels(width, height))
}

/// Bytes of the buffer holding `levels`: one float per texel.
fn bytes(levels: &[Level]) -> u64 {
    let last = levels.last().expect("a pyramid has a level");
    4 * (last.offset + last.width * last.height) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_level_halves_the_one_below_rounding_up_down_to_one_texel() {
        let l = levels(5, 3);
        let sizes: Vec<_> = l.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(5, 3), (3, 2), (2, 1), (1, 1)]);
        let offsets: Vec<_> = l.iter().map(|l| l.offset).collect();
        assert_eq!(offsets, [0, 15, 21, 23]);
        assert_eq!(device_bytes(5, 3), 4 * 24);
        assert_eq!(levels(1280, 720).len(), 12);
        assert_eq!(levels(1, 1).len(), 1);
    }
}
