//! 2D images with one view each: render targets, the shadow map and the
//! mipmapped surface textures.

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::memory::MemoryLocation;
use crate::gpu::Gpu;

pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub samples: vk::SampleCountFlags,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
    allocation: Allocation,
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
        let device = &gpu.device.raw;
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
        // SAFETY: valid create info on a live device.
        let raw =
            unsafe { device.create_image(&info, None) }.vk_context("vkCreateImage", desc.name)?;
        gpu.device.name(raw, desc.name);
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = match gpu.allocate(desc.name, requirements, MemoryLocation::GpuOnly, false)
        {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.destroy_image(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: fresh image, fresh allocation that satisfies its requirements.
        if let Err(r) =
            unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
        {
            unsafe { device.destroy_image(raw, None) };
            gpu.memory.free(allocation);
            return Err(Error::vk("vkBindImageMemory", desc.name, r));
        }
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format)
            .subresource_range(subresource_range(desc.aspect, desc.mip_levels));
        let view = match unsafe { device.create_image_view(&view_info, None) } {
            Ok(v) => v,
            Err(r) => {
                unsafe { device.destroy_image(raw, None) };
                gpu.memory.free(allocation);
                return Err(Error::vk("vkCreateImageView", desc.name, r));
            }
        };
        gpu.device.name(view, &format!("{} view", desc.name));
        Ok(Self {
            raw,
            view,
            format: desc.format,
            extent: desc.extent,
            samples: desc.samples,
            aspect: desc.aspect,
            mip_levels: desc.mip_levels,
            allocation,
        })
    }

    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        subresource_range(self.aspect, self.mip_levels)
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the owner guarantees the GPU no longer uses the image.
        unsafe {
            gpu.device.raw.destroy_image_view(self.view, None);
            gpu.device.raw.destroy_image(self.raw, None);
        }
        gpu.memory.free(self.allocation);
    }
}

pub fn subresource_range(aspect: vk::ImageAspectFlags, levels: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: levels,
        base_array_layer: 0,
        layer_count: 1,
    }
}
