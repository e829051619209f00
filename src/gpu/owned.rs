//! One owner for every Vulkan object that is a single handle destroyed by
//! one call: it holds the device alive, names the object, and destroys it
//! in `Drop`. Buffers and images, which own memory too, have types of
//! their own.

use std::sync::Arc;

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::Gpu;

/// A handle type and the call that destroys it.
pub trait DeviceChild: vk::Handle + Copy {
    /// # Safety
    /// `self` was made from `device`, is not null, is destroyed once, and
    /// no pending GPU work uses it.
    unsafe fn destroy(self, device: &ash::Device);
}

macro_rules! device_child {
    ($($handle:ty => $call:ident),* $(,)?) => {$(
        impl DeviceChild for $handle {
            unsafe fn destroy(self, device: &ash::Device) {
                // SAFETY: the caller upholds this trait method's contract.
                unsafe { device.$call(self, None) }
            }
        }
    )*};
}

device_child! {
    vk::Sampler => destroy_sampler,
    vk::Pipeline => destroy_pipeline,
    vk::PipelineLayout => destroy_pipeline_layout,
    vk::DescriptorSetLayout => destroy_descriptor_set_layout,
    vk::DescriptorPool => destroy_descriptor_pool,
    vk::QueryPool => destroy_query_pool,
    vk::ShaderModule => destroy_shader_module,
    vk::CommandPool => destroy_command_pool,
    vk::Fence => destroy_fence,
    vk::Semaphore => destroy_semaphore,
    vk::ImageView => destroy_image_view,
}

/// A named Vulkan object, destroyed when dropped.
pub struct Owned<H: DeviceChild> {
    device: Arc<Device>,
    raw: H,
}

impl<H: DeviceChild> Owned<H> {
    /// Takes ownership of `raw`, just made from `device`, and names it.
    pub(super) fn new(device: &Arc<Device>, raw: H, name: &str) -> Self {
        device.name(raw, name);
        Self {
            device: device.clone(),
            raw,
        }
    }

    pub(super) fn raw(&self) -> H {
        self.raw
    }

    pub(super) fn device(&self) -> &Arc<Device> {
        &self.device
    }
}

impl<H: DeviceChild> Drop for Owned<H> {
    fn drop(&mut self) {
        // SAFETY: made from this device (`new`), destroyed only here; every
        // submission waits for its fence before returning, so no GPU work
        // still uses it.
        unsafe { self.raw.destroy(&self.device.raw) };
    }
}

/// A sampler (filtering, addressing, comparison).
/// A sampler, shared with the descriptor sets that bind it (released when
/// the last lets go).
#[derive(Clone)]
pub struct Sampler(pub(super) Arc<Owned<vk::Sampler>>);

impl Sampler {
    pub fn new(gpu: &Gpu, info: &vk::SamplerCreateInfo, name: &str) -> Result<Self> {
        let device = gpu.device();
        // SAFETY: a valid create info on a live device.
        let raw =
            unsafe { device.raw.create_sampler(info, None) }.vk_context("vkCreateSampler", name)?;
        Ok(Self(Arc::new(Owned::new(device, raw, name))))
    }

    pub(super) fn raw(&self) -> vk::Sampler {
        self.0.raw()
    }
}
