//! Buffers: a `vk::Buffer` and the memory behind it, owned together.

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::commands::Commands;
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
        let allocation = match gpu.allocate(name, requirements, location, true) {
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

    /// A device-local buffer filled with `bytes` through a staging copy,
    /// made visible to `dst_stage`/`dst_access`. Blocks until the copy is done.
    pub fn with_data(
        gpu: &Gpu,
        commands: &Commands,
        name: &str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
        dst_stage: vk::PipelineStageFlags2,
        dst_access: vk::AccessFlags2,
    ) -> Result<Self> {
        let dst = Buffer::new(
            gpu,
            name,
            bytes.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let mut staging = match Buffer::new(
            gpu,
            &format!("{name} (staging)"),
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        ) {
            Ok(s) => s,
            Err(e) => {
                dst.destroy(gpu);
                return Err(e);
            }
        };
        staging.write(0, bytes);
        let result = (|| {
            let cmd = commands.begin(gpu)?;
            let barrier = [vk::BufferMemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COPY)
                .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                .dst_stage_mask(dst_stage)
                .dst_access_mask(dst_access)
                .buffer(dst.raw)
                .offset(0)
                .size(vk::WHOLE_SIZE)];
            let region = vk::BufferCopy {
                src_offset: 0,
                dst_offset: 0,
                size: dst.size,
            };
            // SAFETY: both buffers are live and `size` bytes long; recording.
            unsafe {
                gpu.device
                    .raw
                    .cmd_copy_buffer(cmd, staging.raw, dst.raw, &[region]);
                gpu.device.raw.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().buffer_memory_barriers(&barrier),
                );
            }
            commands.submit_and_wait(gpu, &format!("uploading {name}"))
        })();
        staging.destroy(gpu);
        match result {
            Ok(()) => Ok(dst),
            Err(e) => {
                dst.destroy(gpu);
                Err(e)
            }
        }
    }

    /// Copies the first `count` values of a device buffer (made with
    /// TRANSFER_SRC) to the host, after every earlier write to it: for
    /// tests, pictures and statistics, never per frame. Blocks.
    pub fn read_back<T: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        commands: &Commands,
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
        let result = (|| {
            let cmd = commands.begin(gpu)?;
            let to_copy = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
                .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::COPY)
                .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)];
            let to_host = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COPY)
                .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            // SAFETY: recording; both buffers are live and at least `bytes` long.
            unsafe {
                let device = &gpu.device.raw;
                device.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().memory_barriers(&to_copy),
                );
                if bytes > 0 {
                    let region = vk::BufferCopy {
                        src_offset: 0,
                        dst_offset: 0,
                        size: bytes,
                    };
                    device.cmd_copy_buffer(cmd, self.raw, host.raw, &[region]);
                }
                device.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().memory_barriers(&to_host),
                );
            }
            commands.submit_and_wait(gpu, "reading a buffer back")
        })();
        let out = result.map(|()| {
            let mapped = host.mapped().expect("readback memory is host-visible");
            bytemuck::pod_collect_to_vec(&mapped[..bytes as usize])
        });
        host.destroy(gpu);
        out
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer.
        unsafe { gpu.device.raw.destroy_buffer(self.raw, None) };
        gpu.memory.free(self.allocation);
    }
}
