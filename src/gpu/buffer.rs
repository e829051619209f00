//! Buffers: a `vk::Buffer` and the memory behind it, owned together.

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::memory::MemoryLocation;
use crate::gpu::Gpu;

pub struct Buffer {
    pub raw: vk::Buffer,
    pub size: vk::DeviceSize,
    allocation: Allocation,
}

impl Buffer {
    pub fn new(
        gpu: &Gpu,
        name: &str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        if size == 0 {
            return Err(Error::InvalidInput(format!(
                "buffer {name:?} would be empty"
            )));
        }
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &gpu.device.raw;
        // SAFETY: a valid create info on a live device.
        let raw =
            unsafe { device.create_buffer(&info, None) }.vk_context("vkCreateBuffer", name)?;
        gpu.device.name(raw, name);
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = match gpu.memory.allocate(name, requirements, location, true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: unbound and unused.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: the allocation satisfies `requirements` and is not bound elsewhere.
        if let Err(r) =
            unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
        {
            unsafe { device.destroy_buffer(raw, None) };
            gpu.memory.free(allocation);
            return Err(Error::vk("vkBindBufferMemory", name, r));
        }
        Ok(Self {
            raw,
            size,
            allocation,
        })
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.mapped_slice()
    }

    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.allocation.mapped_slice_mut()
    }

    /// Copies `data` into a host-visible buffer at `offset`.
    pub fn write<T: bytemuck::Pod>(&mut self, offset: usize, data: &[T]) {
        let bytes = bytemuck::cast_slice(data);
        let mapped = self
            .mapped_mut()
            .expect("write to a buffer that is not host-visible");
        mapped[offset..offset + bytes.len()].copy_from_slice(bytes);
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer.
        unsafe { gpu.device.raw.destroy_buffer(self.raw, None) };
        gpu.memory.free(self.allocation);
    }
}
