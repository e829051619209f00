//! Descriptor-set bindings as Rust declares them, the pipeline layout of
//! one such set (with at most one push-constant range), and a descriptor
//! set of buffers, images and samplers with a pool of its own: what every
//! pass binds, made one way.

use std::any::Any;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::owned::{Owned, Sampler};
use crate::gpu::{Buffer, Gpu, Image};

/// The descriptor types meadow uses, comparable with `vk::DescriptorType`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DescriptorKind {
    UniformBuffer,
    StorageBuffer,
    CombinedImageSampler,
    SampledImage,
    StorageImage,
    Sampler,
}

impl DescriptorKind {
    pub fn vk(self) -> vk::DescriptorType {
        match self {
            DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
            DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
            DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
        }
    }
}

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

/// What a pipeline layout declares: each binding's (set, binding, kind,
/// stages), the push block's size and stages (the GPU makes each once).
#[derive(PartialEq, Eq, Hash)]
pub(super) struct LayoutKey {
    bindings: Vec<(u32, u32, DescriptorKind, u32)>,
    push_size: u32,
    push_stages: u32,
}

/// A set layout of some bindings and the pipeline layout of that one set,
/// with an optional push-constant range at offset 0.
pub struct PipelineLayout {
    pub(super) raw: Owned<vk::PipelineLayout>,
    pub(super) set_layout: Owned<vk::DescriptorSetLayout>,
    pub(super) push_stages: vk::ShaderStageFlags,
}

impl PipelineLayout {
    /// `push`: the stages that read a push-constant block of `P`'s size;
    /// use `()` and empty stages for none. Made once per device: a layout
    /// declaring the same is the one made first (`gpu::made_once`), with
    /// its name.
    pub fn new<P>(
        gpu: &Gpu,
        bindings: &[LayoutBinding],
        push_stages: vk::ShaderStageFlags,
        name: &str,
    ) -> Result<Arc<Self>> {
        let size = std::mem::size_of::<P>() as u32;
        let key = LayoutKey {
            bindings: bindings
                .iter()
                .map(|b| (b.set, b.binding, b.ty, b.stages.as_raw()))
                .collect(),
            push_size: size,
            push_stages: push_stages.as_raw(),
        };
        gpu.layouts
            .get(key, || Self::made(gpu, bindings, size, push_stages, name))
    }

    /// A new layout, as `new` describes it, with a push block of `size`
    /// bytes.
    fn made(
        gpu: &Gpu,
        bindings: &[LayoutBinding],
        size: u32,
        push_stages: vk::ShaderStageFlags,
        name: &str,
    ) -> Result<Arc<Self>> {
        let device = gpu.device();
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
        let set_name = format!("{name} set layout");
        // SAFETY: a valid create info on a live device.
        let set_layout = unsafe { device.raw.create_descriptor_set_layout(&info, None) }
            .vk_context("vkCreateDescriptorSetLayout", &set_name)?;
        let set_layout = Owned::new(device, set_layout, &set_name);
        let ranges: Vec<vk::PushConstantRange> = (size > 0 && !push_stages.is_empty())
            .then_some(vk::PushConstantRange {
                stage_flags: push_stages,
                offset: 0,
                size,
            })
            .into_iter()
            .collect();
        let set_layouts = [set_layout.raw()];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&ranges);
        let layout_name = format!("{name} pipeline layout");
        // SAFETY: a valid create info; the set layout is live.
        let raw = unsafe { device.raw.create_pipeline_layout(&info, None) }
            .vk_context("vkCreatePipelineLayout", &layout_name)?;
        Ok(Arc::new(Self {
            raw: Owned::new(device, raw, &layout_name),
            set_layout,
            push_stages,
        }))
    }

    pub(super) fn raw(&self) -> vk::PipelineLayout {
        self.raw.raw()
    }
}

/// What one binding of a set points at. The set keeps it alive (it holds
/// the buffer's, image's or sampler's core), so the owners of a set and of
/// what it binds may drop in any order.
#[derive(Clone, Copy)]
pub enum Bound<'a> {
    /// A whole buffer (uniform or storage).
    Buffer(&'a Buffer),
    /// `size` bytes of a storage buffer from `offset`: one batch of a
    /// kernel over a buffer larger than one binding may reach
    /// (`gpu::batches`).
    Part {
        buffer: &'a Buffer,
        offset: u64,
        size: u64,
    },
    /// A sampled image, read in the shader-read-only layout.
    Image(&'a Image),
    /// A sampler on its own.
    Sampler(&'a Sampler),
}

/// One descriptor set in a pool sized for exactly it; dropping it drops
/// the pool, which frees the set, then lets go of what it binds.
pub struct DescriptorSet {
    _pool: Owned<vk::DescriptorPool>,
    pub(super) raw: vk::DescriptorSet,
    /// What it binds (buffers', images' and samplers' cores), kept alive
    /// by it and never read through it.
    _held: Vec<Arc<dyn Any>>,
}

impl DescriptorSet {
    /// Allocates set 0 of `layout` and points binding `bindings[i]` at
    /// `bound[i]` (`bindings` being the ones the layout was made from).
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn new(
        gpu: &Gpu,
        layout: &PipelineLayout,
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
        check_ranges(gpu, bindings, bound, name)?;
        let device: &Arc<Device> = gpu.device();
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
        // SAFETY: a valid create info on a live device.
        let pool = unsafe { device.raw.create_descriptor_pool(&pool_info, None) }
            .vk_context("vkCreateDescriptorPool", name)?;
        let pool = Owned::new(device, pool, &format!("{name} pool"));
        let layouts = [layout.set_layout.raw()];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool.raw())
            .set_layouts(&layouts);
        // SAFETY: the pool was sized for exactly this set.
        let raw = unsafe { device.raw.allocate_descriptor_sets(&alloc) }
            .vk_context("vkAllocateDescriptorSets", name)?[0];
        device.name(raw, name);
        let buffer_infos: Vec<[vk::DescriptorBufferInfo; 1]> = bound
            .iter()
            .map(|r| match r {
                Bound::Buffer(buffer) => [vk::DescriptorBufferInfo {
                    buffer: buffer.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }],
                Bound::Part {
                    buffer,
                    offset,
                    size,
                } => [vk::DescriptorBufferInfo {
                    buffer: buffer.raw,
                    offset: *offset,
                    range: *size,
                }],
                Bound::Image(_) | Bound::Sampler(_) => [vk::DescriptorBufferInfo::default()],
            })
            .collect();
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = bound
            .iter()
            .map(|r| match r {
                Bound::Image(image) => [vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: image.view,
                    image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }],
                Bound::Sampler(sampler) => [vk::DescriptorImageInfo {
                    sampler: sampler.raw(),
                    ..Default::default()
                }],
                Bound::Buffer(_) | Bound::Part { .. } => [vk::DescriptorImageInfo::default()],
            })
            .collect();
        let writes: Vec<_> = bindings
            .iter()
            .zip(bound)
            .zip(buffer_infos.iter().zip(&image_infos))
            .map(|((b, r), (buffer_info, image_info))| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(raw)
                    .dst_binding(b.binding)
                    .descriptor_type(b.ty.vk());
                match r {
                    Bound::Buffer(_) | Bound::Part { .. } => write.buffer_info(buffer_info),
                    Bound::Image(_) | Bound::Sampler(_) => write.image_info(image_info),
                }
            })
            .collect();
        // SAFETY: the set is new and not used by any command buffer; every
        // resource written is live.
        unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
        let held = bound
            .iter()
            .map(|r| -> Arc<dyn Any> {
                match r {
                    Bound::Buffer(buffer) | Bound::Part { buffer, .. } => buffer.core.clone(),
                    Bound::Image(image) => image.core.clone(),
                    Bound::Sampler(sampler) => sampler.0.clone(),
                }
            })
            .collect();
        Ok(Self {
            _pool: pool,
            raw,
            _held: held,
        })
    }
}

/// Refuses a buffer binding past what this device lets one descriptor
/// reach (maxStorageBufferRange, maxUniformBufferRange: lavapipe's storage
/// range is 128 MiB, a million blades' control points), or a part that is
/// not inside its buffer or not aligned: invalid usage the driver need not
/// catch. Kernels over bigger buffers run in batches (`gpu::batches`).
fn check_ranges(gpu: &Gpu, bindings: &[LayoutBinding], bound: &[Bound], name: &str) -> Result<()> {
    let limits = gpu.limits();
    for (b, r) in bindings.iter().zip(bound) {
        let (buffer, offset, size) = match *r {
            Bound::Buffer(buffer) => (buffer, 0, buffer.size),
            Bound::Part {
                buffer,
                offset,
                size,
            } => (buffer, offset, size),
            Bound::Image(_) | Bound::Sampler(_) => continue,
        };
        let (most, align, limit) = match b.ty {
            DescriptorKind::UniformBuffer => (
                limits.max_uniform_buffer_range as u64,
                limits.min_uniform_buffer_offset_alignment,
                "maxUniformBufferRange",
            ),
            DescriptorKind::StorageBuffer => (
                limits.max_storage_buffer_range as u64,
                limits.min_storage_buffer_offset_alignment,
                "maxStorageBufferRange",
            ),
            _ => continue,
        };
        if offset.checked_add(size).is_none_or(|end| end > buffer.size)
            || size == 0
            || offset % align.max(1) != 0
        {
            return Err(Error::InvalidInput(format!(
                "{name}: binding {} would reach bytes {offset}..{} of a {}-byte buffer, offset aligned to {align}",
                b.binding,
                offset.saturating_add(size),
                buffer.size
            )));
        }
        if size > most {
            return Err(Error::InvalidInput(format!(
                "{name}: binding {} would reach {size} bytes, over this device's {limit} of {most}; make the scene smaller (fewer wind cells or blades)",
                b.binding
            )));
        }
    }
    Ok(())
}
