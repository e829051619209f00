//! 2D images with one view each: render targets, the shadow map and the
//! mipmapped surface textures. The image, its memory and its view are
//! released together in `Drop`.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::memory::MemoryLocation;
use crate::gpu::Gpu;

pub struct Image {
    pub(super) core: Arc<ImageCore>,
    pub(super) raw: vk::Image,
    pub(super) view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub samples: vk::SampleCountFlags,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
    /// The layout the last recording that declared a use of it left it
    /// in (src/gpu/sync.rs starts the next from there).
    pub(super) layout: Cell<vk::ImageLayout>,
}

/// The Vulkan image, its view and its memory, released in `Drop` when the
/// last holder (the `Image`, or a descriptor set sampling it) lets go.
pub(super) struct ImageCore {
    device: Arc<Device>,
    raw: vk::Image,
    view: vk::ImageView,
    /// None only while `new` has not bound memory yet.
    allocation: Option<Allocation>,
}

pub struct ImageDesc<'a> {
    pub name: &'a str,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub samples: vk::SampleCountFlags,
    pub usage: vk::ImageUsageFlags,
    pub aspect: vk::ImageAspectFlags,
    /// 1 for render targets; a full chain for textures.
    pub mip_levels: u32,
}

impl Image {
    pub fn new(gpu: &Gpu, desc: &ImageDesc) -> Result<Self> {
        let device = gpu.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.extent.width,
                height: desc.extent.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a valid create info on a live device.
        let raw = unsafe { device.raw.create_image(&info, None) }
            .vk_context("vkCreateImage", desc.name)?;
        device.name(raw, desc.name);
        // Owned from here on: a failure below drops it, which releases it.
        let mut core = ImageCore {
            device: device.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
        };
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.raw.get_image_memory_requirements(raw) };
        let allocation =
            device.allocate(desc.name, requirements, MemoryLocation::GpuOnly, false)?;
        // SAFETY: the memory handle is only bound, never freed, here; the
        // allocation (kept with the object) owns it.
        let memory = unsafe { allocation.memory() };
        let offset = allocation.offset();
        core.allocation = Some(allocation);
        // SAFETY: a fresh image and an allocation that satisfies its
        // requirements, bound once.
        unsafe { device.raw.bind_image_memory(raw, memory, offset) }
            .vk_context("vkBindImageMemory", desc.name)?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format)
            .subresource_range(range(desc.aspect, desc.mip_levels));
        // SAFETY: the image is live and bound; the info describes all of it.
        core.view = unsafe { device.raw.create_image_view(&view_info, None) }
            .vk_context("vkCreateImageView", desc.name)?;
        device.name(core.view, &format!("{} view", desc.name));
        Ok(Self {
            raw,
            view: core.view,
            core: Arc::new(core),
            format: desc.format,
            extent: desc.extent,
            samples: desc.samples,
            aspect: desc.aspect,
            mip_levels: desc.mip_levels,
            layout: Cell::new(vk::ImageLayout::UNDEFINED),
        })
    }

    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        range(self.aspect, self.mip_levels)
    }
}

/// All of an image's levels (one layer).
fn range(aspect: vk::ImageAspectFlags, mip_levels: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: mip_levels,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl Drop for ImageCore {
    fn drop(&mut self) {
        // SAFETY: the view and the image were made from this device in
        // `new` and are destroyed only here, when the last holder lets go (a
        // null view is a no-op); every submission is waited for before it
        // returns, so no GPU work uses them.
        unsafe { self.device.raw.destroy_image_view(self.view, None) };
        // SAFETY: as above.
        unsafe { self.device.raw.destroy_image(self.raw, None) };
        if let Some(allocation) = self.allocation.take() {
            self.device.memory.free(allocation);
        }
    }
}
