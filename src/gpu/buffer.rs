//! Buffers: a `vk::Buffer` and the memory behind it, owned together and
//! released together when the last holder lets go: the `Buffer`, or a
//! descriptor set that binds it (src/gpu/descriptors.rs), so a set never
//! points at a released buffer whatever order their owners drop in.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::barrier::Access;
use crate::gpu::command_pool::CommandPool;
use crate::gpu::device::Device;
use crate::gpu::memory::MemoryLocation;
use crate::gpu::sync::BufferUse;
use crate::gpu::Gpu;

pub struct Buffer {
    pub(super) core: Arc<BufferCore>,
    pub(super) raw: vk::Buffer,
    pub size: vk::DeviceSize,
}

/// The Vulkan buffer and its memory, released in `Drop`.
pub(super) struct BufferCore {
    device: Arc<Device>,
    raw: vk::Buffer,
    /// None only while `new` has not bound memory yet.
    allocation: Option<Allocation>,
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
        let device = gpu.device();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: a valid create info on a live device.
        let raw =
            unsafe { device.raw.create_buffer(&info, None) }.vk_context("vkCreateBuffer", name)?;
        device.name(raw, name);
        // Owned from here on: a failure below drops it, which releases it.
        let mut core = BufferCore {
            device: device.clone(),
            raw,
            allocation: None,
        };
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.raw.get_buffer_memory_requirements(raw) };
        let allocation = device.allocate(name, requirements, location, true)?;
        // SAFETY: the memory handle is only bound, never freed, here; the
        // allocation (kept with the object) owns it.
        let memory = unsafe { allocation.memory() };
        let offset = allocation.offset();
        core.allocation = Some(allocation);
        // SAFETY: the allocation satisfies `requirements` and is bound once.
        unsafe { device.raw.bind_buffer_memory(raw, memory, offset) }
            .vk_context("vkBindBufferMemory", name)?;
        Ok(Self {
            core: Arc::new(core),
            raw,
            size,
        })
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Option<&[u8]> {
        self.core.allocation.as_ref()?.mapped_slice()
    }

    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        let allocation = self.core.allocation.as_ref()?;
        let ptr = allocation.mapped_ptr()?;
        // SAFETY: the mapping covers the allocation's size and lives as
        // long as the core; `&mut self` is the only way to it: descriptor
        // sets hold the core only to keep it alive, never map it.
        Some(unsafe {
            std::slice::from_raw_parts_mut(ptr.as_ptr().cast::<u8>(), allocation.size() as usize)
        })
    }

    /// Copies `data` into a host-visible buffer at `offset`.
    pub fn write<T: bytemuck::Pod>(&mut self, offset: usize, data: &[T]) {
        let bytes = bytemuck::cast_slice(data);
        let mapped = self
            .mapped_mut()
            .expect("write to a buffer that is not host-visible");
        mapped[offset..offset + bytes.len()].copy_from_slice(bytes);
    }

    /// A device-local buffer filled with `bytes` through a staging copy,
    /// made visible to `then` (the access that reads it next). Blocks until
    /// the copy is done.
    pub fn with_data(
        gpu: &Gpu,
        commands: &CommandPool,
        name: &str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
        then: Access,
    ) -> Result<Self> {
        let dst = Buffer::new(
            gpu,
            name,
            bytes.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        dst.upload(gpu, commands, name, bytes, then)?;
        Ok(dst)
    }

    /// Overwrites the start of a buffer made with TRANSFER_DST with
    /// `bytes` through a staging copy, after every earlier access and
    /// visible to `then`. Blocks until the copy is done: call between
    /// submissions.
    pub fn upload(
        &self,
        gpu: &Gpu,
        commands: &CommandPool,
        name: &str,
        bytes: &[u8],
        then: Access,
    ) -> Result<()> {
        if bytes.len() as u64 > self.size {
            return Err(Error::InvalidInput(format!(
                "{} bytes do not fit the {}-byte buffer {name:?}",
                bytes.len(),
                self.size
            )));
        }
        let mut staging = Buffer::new(
            gpu,
            &format!("{name} (staging)"),
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(0, bytes);
        let rec = commands.begin()?;
        // The first use in this recording waits for every earlier one.
        rec.uses(&[
            BufferUse::new(self, Access::COPY_WRITE),
            BufferUse::new(&staging, Access::COPY_READ),
        ]);
        rec.copy_buffer(&staging, self, bytes.len() as u64);
        rec.uses(&[BufferUse::new(self, then)]);
        rec.submit_and_wait(&format!("uploading {name}"))?;
        Ok(())
    }

    /// Copies the first `count` values of a device buffer (made with
    /// TRANSFER_SRC) to the host, after every earlier write to it: for
    /// tests, pictures and statistics, never per frame. Blocks.
    pub fn read_back<T: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        commands: &CommandPool,
        count: usize,
    ) -> Result<Vec<T>> {
        let bytes = (count * std::mem::size_of::<T>()) as u64;
        if bytes > self.size {
            return Err(Error::InvalidInput(format!(
                "reading {bytes} bytes back from a {}-byte buffer",
                self.size
            )));
        }
        let host = Buffer::new(
            gpu,
            "readback",
            bytes.max(4),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let rec = commands.begin()?;
        rec.uses(&[
            BufferUse::new(self, Access::COPY_READ),
            BufferUse::new(&host, Access::COPY_WRITE),
        ]);
        if bytes > 0 {
            rec.copy_buffer(self, &host, bytes);
        }
        rec.uses(&[BufferUse::new(&host, Access::HOST_READ)]);
        rec.submit_and_wait("reading a buffer back")?;
        let mapped = host.mapped().expect("readback memory is host-visible");
        Ok(bytemuck::pod_collect_to_vec(&mapped[..bytes as usize]))
    }
}

impl Drop for BufferCore {
    fn drop(&mut self) {
        // SAFETY: made from this device in `new`, destroyed only here, when
        // its last holder lets go; every submission is waited for before it
        // returns, so no GPU work uses it.
        unsafe { self.device.raw.destroy_buffer(self.raw, None) };
        if let Some(allocation) = self.allocation.take() {
            self.device.memory.free(allocation);
        }
    }
}
