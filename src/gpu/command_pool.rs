//! A command pool with one primary command buffer and a fence: `begin` a
//! `Recording` (src/gpu/recording.rs), record into it, submit and wait, or
//! submit and go on (`Recording::submit`: the pool waits before its next
//! `begin`, and before it goes). Its submissions go to the device's main
//! queue, or with `on_simulation_queue` to the queue beside it where the
//! device has one.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::journal::Journal;
use crate::gpu::owned::Owned;
use crate::gpu::recording::{wait_for_fence, Recording};
use crate::gpu::Gpu;

pub struct CommandPool {
    device: Arc<Device>,
    fence: Owned<vk::Fence>,
    pool: Owned<vk::CommandPool>,
    cmd: vk::CommandBuffer,
    queue: vk::Queue,
    /// A submission not waited for yet (`Recording::submit`).
    in_flight: Cell<bool>,
    /// What its recordings do, in words, when started (src/gpu/journal.rs).
    journal: Journal,
}

impl CommandPool {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        Self::on_queue(gpu, name, gpu.device().queue)
    }

    /// A pool whose submissions go to the queue beside the main one
    /// (`Gpu::has_simulation_queue`), or to the main queue where the
    /// device has one queue: the same protocol, in order on one queue.
    pub fn on_simulation_queue(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = gpu.device();
        Self::on_queue(gpu, name, device.compute_queue.unwrap_or(device.queue))
    }

    fn on_queue(gpu: &Gpu, name: &str, queue: vk::Queue) -> Result<Self> {
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
            queue,
            in_flight: Cell::new(false),
            journal: Journal::default(),
        })
    }

    /// Waits for the pool's last submission if it is still in flight.
    pub fn wait(&self, what: &str) -> Result<()> {
        if !self.in_flight.get() {
            return Ok(());
        }
        let waited = wait_for_fence(&self.device, self.fence.raw(), what);
        // Waited for, or lost with the device idle: nothing is left to wait for.
        self.in_flight.set(false);
        waited
    }

    /// This pool's journal: start it, record, take its lines.
    pub fn journal(&self) -> &Journal {
        &self.journal
    }

    /// Resets the pool (and so its one command buffer) and begins recording.
    pub fn begin(&self) -> Result<Recording<'_>> {
        self.wait("the pool's last submission, before recording again")?;
        let device = &self.device.raw;
        // SAFETY: the previous submission (if any) was waited for, in
        // `submit_and_wait` or just above, so the pool's buffer is not in
        // flight.
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
            queue: self.queue,
            in_flight: &self.in_flight,
            tracker: Default::default(),
            journal: &self.journal,
            dispatches: Default::default(),
        })
    }
}

impl Drop for CommandPool {
    fn drop(&mut self) {
        // The buffer, the pool and what the work reads may not go while it
        // runs; a failure here (the device lost) leaves nothing running.
        let _ = self.wait("the pool's last submission, before it goes");
    }
}
