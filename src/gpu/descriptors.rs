//! Descriptor-set layouts, pipeline layouts, and a descriptor set of
//! buffers with a pool of its own: what every pass binds, made one way.

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::Gpu;
use crate::reflect::DescriptorKind;

/// One binding of a descriptor-set layout, as Rust declares it. The
/// reflection tests check these against the compiled shaders.
#[derive(Clone, Copy, Debug)]
pub struct LayoutBinding {
    pub set: u32,
    pub binding: u32,
    pub ty: DescriptorKind,
    pub stages: vk::ShaderStageFlags,
}

impl LayoutBinding {
    /// A storage buffer at set 0 for a compute kernel.
    pub const fn compute_storage(binding: u32) -> Self {
        Self {
            set: 0,
            binding,
            ty: DescriptorKind::StorageBuffer,
            stages: vk::ShaderStageFlags::COMPUTE,
        }
    }
}

pub fn create_set_layout(
    gpu: &Gpu,
    bindings: &[LayoutBinding],
    name: &str,
) -> Result<vk::DescriptorSetLayout> {
    let vk_bindings: Vec<_> = bindings
        .iter()
        .map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b.binding)
                .descriptor_type(b.ty.vk())
                .descriptor_count(1)
                .stage_flags(b.stages)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&vk_bindings);
    // SAFETY: valid create info on a live device.
    let layout = unsafe { gpu.device.raw.create_descriptor_set_layout(&info, None) }
        .vk_context("vkCreateDescriptorSetLayout", name)?;
    gpu.device.name(layout, name);
    Ok(layout)
}

/// A pipeline layout of one set layout and, when `push` is given, one
/// push-constant range (stages, bytes) at offset 0.
pub fn create_pipeline_layout(
    gpu: &Gpu,
    set_layout: vk::DescriptorSetLayout,
    push: Option<(vk::ShaderStageFlags, u32)>,
    name: &str,
) -> Result<vk::PipelineLayout> {
    let set_layouts = [set_layout];
    let ranges: Vec<vk::PushConstantRange> = push
        .map(|(stage_flags, size)| vk::PushConstantRange {
            stage_flags,
            offset: 0,
            size,
        })
        .into_iter()
        .collect();
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&ranges);
    // SAFETY: valid create info; the set layout is live.
    let layout = unsafe { gpu.device.raw.create_pipeline_layout(&info, None) }
        .vk_context("vkCreatePipelineLayout", name)?;
    gpu.device.name(layout, name);
    Ok(layout)
}

/// What one binding of a set points at.
#[derive(Clone, Copy, Debug)]
pub enum Bound {
    /// A whole buffer (uniform or storage).
    Buffer(vk::Buffer),
    /// A sampled image view, in the layout it is read in.
    Image {
        view: vk::ImageView,
        layout: vk::ImageLayout,
    },
    /// A sampler on its own.
    Sampler(vk::Sampler),
}

/// One descriptor set whose bindings are whole buffers (and sampled
/// images), in a pool sized for exactly it.
pub struct BufferSet {
    pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl BufferSet {
    /// Allocates a set of `layout` and points binding `bindings[i]` at
    /// `buffers[i]`.
    pub fn new(
        gpu: &Gpu,
        layout: vk::DescriptorSetLayout,
        bindings: &[LayoutBinding],
        buffers: &[vk::Buffer],
        name: &str,
    ) -> Result<Self> {
        let bound: Vec<Bound> = buffers.iter().map(|&b| Bound::Buffer(b)).collect();
        Self::with(gpu, layout, bindings, &bound, name)
    }

    /// Allocates a set of `layout` and points binding `bindings[i]` at
    /// `bound[i]`.
    pub fn with(
        gpu: &Gpu,
        layout: vk::DescriptorSetLayout,
        bindings: &[LayoutBinding],
        bound: &[Bound],
        name: &str,
    ) -> Result<Self> {
        if bindings.len() != bound.len() {
            return Err(Error::InvalidInput(format!(
                "{name}: {} bindings but {} resources",
                bindings.len(),
                bound.len()
            )));
        }
        let device = &gpu.device.raw;
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for b in bindings {
            match sizes.iter_mut().find(|s| s.ty == b.ty.vk()) {
                Some(s) => s.descriptor_count += 1,
                None => sizes.push(vk::DescriptorPoolSize {
                    ty: b.ty.vk(),
                    descriptor_count: 1,
                }),
            }
        }
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid create info on a live device.
        let pool = unsafe { device.create_descriptor_pool(&pool_info, None) }
            .vk_context("vkCreateDescriptorPool", name)?;
        gpu.device.name(pool, &format!("{name} pool"));
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool was sized for exactly this set.
        let set = match unsafe { device.allocate_descriptor_sets(&alloc) } {
            Ok(sets) => sets[0],
            Err(r) => {
                unsafe { device.destroy_descriptor_pool(pool, None) };
                return Err(Error::vk("vkAllocateDescriptorSets", name, r));
            }
        };
        gpu.device.name(set, name);
        let buffer_infos: Vec<[vk::DescriptorBufferInfo; 1]> = bound
            .iter()
            .map(|r| match *r {
                Bound::Buffer(buffer) => [vk::DescriptorBufferInfo {
                    buffer,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }],
                Bound::Image { .. } | Bound::Sampler(_) => [vk::DescriptorBufferInfo::default()],
            })
            .collect();
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = bound
            .iter()
            .map(|r| match *r {
                Bound::Image { view, layout } => [vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: view,
                    image_layout: layout,
                }],
                Bound::Sampler(sampler) => [vk::DescriptorImageInfo {
                    sampler,
                    ..Default::default()
                }],
                Bound::Buffer(_) => [vk::DescriptorImageInfo::default()],
            })
            .collect();
        let writes: Vec<_> = bindings
            .iter()
            .zip(bound)
            .zip(buffer_infos.iter().zip(&image_infos))
            .map(|((b, r), (buffer_info, image_info))| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(b.binding)
                    .descriptor_type(b.ty.vk());
                match r {
                    Bound::Buffer(_) => write.buffer_info(buffer_info),
                    Bound::Image { .. } | Bound::Sampler(_) => write.image_info(image_info),
                }
            })
            .collect();
        // SAFETY: the set is new and not used by any command buffer.
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        Ok(Self { pool, set })
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the owner waited for the GPU to finish with the set;
        // destroying the pool frees it.
        unsafe { gpu.device.raw.destroy_descriptor_pool(self.pool, None) };
    }
}
