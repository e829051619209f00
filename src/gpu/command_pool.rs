//! A command pool with one primary command buffer and a fence: `begin` a
//! `Recording` (src/gpu/recording.rs), record into it, submit and wait.
//! Offscreen rendering needs nothing more.

use std::sync::Arc;

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::journal::Journal;
use crate::gpu::owned::Owned;
use crate::gpu::recording::Recording;
use crate::gpu::Gpu;

pub struct CommandPool {
    device: Arc<Device>,
    fence: Owned<vk::Fence>,
    pool: Owned<vk::CommandPool>,
    cmd: vk::CommandBuffer,
    /// What its recordings do, in words, when started (src/gpu/journal.rs).
    journal: Journal,
}

impl CommandPool {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = gpu.device();
        // One buffer per pool: resetting the pool resets it, cheaper than
        // a pool that tracks buffers for resetting one by one.
        let pool_info =
            vk::CommandPoolCreateInfo::default().queue_family_index(device.queue_family);
        // SAFETY: a valid create info on a live device.
        let pool = unsafe { device.raw.create_command_pool(&pool_info, None) }
            .vk_context("vkCreateCommandPool", name)?;
        let pool = Owned::new(device, pool, &format!("{name} pool"));
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool.raw())
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is live; its buffers are freed with it.
        let cmd = unsafe { device.raw.allocate_command_buffers(&alloc) }
            .vk_context("vkAllocateCommandBuffers", name)?[0];
        device.name(cmd, name);
        // SAFETY: a valid create info on a live device.
        let fence = unsafe {
            device
                .raw
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .vk_context("vkCreateFence", name)?;
        let fence = Owned::new(device, fence, &format!("{name} fence"));
        Ok(Self {
            device: device.clone(),
            fence,
            pool,
            cmd,
            journal: Journal::default(),
        })
    }

    /// This pool's journal: start it, record, take its lines.
    pub fn journal(&self) -> &Journal {
        &self.journal
    }

    /// Resets the pool (and so its one command buffer) and begins recording.
    pub fn begin(&self) -> Result<Recording<'_>> {
        let device = &self.device.raw;
        // SAFETY: the previous submission (if any) was waited for in
        // `submit_and_wait`, so the pool's buffer is not in flight.
        unsafe { device.reset_command_pool(self.pool.raw(), vk::CommandPoolResetFlags::empty()) }
            .vk_context("vkResetCommandPool", "frame commands")?;
        let info = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the buffer was just reset (initial state).
        unsafe { device.begin_command_buffer(self.cmd, &info) }
            .vk_context("vkBeginCommandBuffer", "frame commands")?;
        Ok(Recording {
            device: &self.device,
            cmd: self.cmd,
            fence: self.fence.raw(),
            tracker: Default::default(),
            journal: &self.journal,
            dispatches: Default::default(),
        })
    }
}
