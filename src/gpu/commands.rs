//! A command pool with one primary command buffer and a fence: record,
//! submit, wait. Offscreen rendering needs nothing more.

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::Gpu;

pub struct Commands {
    pool: vk::CommandPool,
    pub cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

/// How long one submission may run before we call the device hung (lavapipe
/// renders big scenes slowly, so this is generous).
const SUBMIT_TIMEOUT_NS: u64 = 600 * 1_000_000_000;

impl Commands {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = &gpu.device.raw;
        // One buffer per pool: resetting the pool resets it, cheaper than
        // a pool that tracks buffers for resetting one by one.
        let pool_info =
            vk::CommandPoolCreateInfo::default().queue_family_index(gpu.device.queue_family);
        // SAFETY: valid create info on a live device.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }
            .vk_context("vkCreateCommandPool", name)?;
        gpu.device.name(pool, &format!("{name} pool"));
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd = match unsafe { device.allocate_command_buffers(&alloc) } {
            Ok(v) => v[0],
            Err(r) => {
                unsafe { device.destroy_command_pool(pool, None) };
                return Err(Error::vk("vkAllocateCommandBuffers", name, r));
            }
        };
        gpu.device.name(cmd, name);
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(r) => {
                unsafe { device.destroy_command_pool(pool, None) };
                return Err(Error::vk("vkCreateFence", name, r));
            }
        };
        gpu.device.name(fence, &format!("{name} fence"));
        Ok(Self { pool, cmd, fence })
    }

    /// Resets the pool (and so its one command buffer) and begins recording.
    pub fn begin(&self, gpu: &Gpu) -> Result<vk::CommandBuffer> {
        let device = &gpu.device.raw;
        // SAFETY: the previous submission (if any) was waited for in `submit_and_wait`.
        unsafe {
            device
                .reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty())
                .vk_context("vkResetCommandPool", "frame commands")?;
            device
                .begin_command_buffer(
                    self.cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .vk_context("vkBeginCommandBuffer", "frame commands")?;
        }
        Ok(self.cmd)
    }

    /// Ends recording, submits, and blocks until the GPU is done.
    pub fn submit_and_wait(&self, gpu: &Gpu, what: &str) -> Result<()> {
        let device = &gpu.device.raw;
        // SAFETY: `cmd` is in the recording state (begun by `begin`).
        unsafe { device.end_command_buffer(self.cmd) }.vk_context("vkEndCommandBuffer", what)?;
        gpu.faults.submission(what)?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the fence is unsignalled (reset after every wait) and the
        // command buffer is not in flight.
        unsafe {
            device
                .queue_submit2(gpu.device.queue, &submit, self.fence)
                .vk_context("vkQueueSubmit2", what)?;
        }
        let waited = unsafe { device.wait_for_fences(&[self.fence], true, SUBMIT_TIMEOUT_NS) };
        match waited {
            Ok(()) => {}
            Err(vk::Result::TIMEOUT) => {
                return Err(Error::DeviceLost {
                    during: format!(
                        "{what} (no answer within {} s)",
                        SUBMIT_TIMEOUT_NS / 1_000_000_000
                    ),
                })
            }
            Err(r) => return Err(Error::vk("vkWaitForFences", what, r)),
        }
        unsafe { device.reset_fences(&[self.fence]) }.vk_context("vkResetFences", what)?;
        Ok(())
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: no submission is in flight (each is waited for).
        unsafe {
            gpu.device.raw.destroy_fence(self.fence, None);
            gpu.device.raw.destroy_command_pool(self.pool, None);
        }
    }
}
