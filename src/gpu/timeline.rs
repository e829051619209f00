//! A timeline semaphore: a counter on the device that submissions signal
//! to a value and wait for (Vulkan 1.2's `timelineSemaphore`). Two queues
//! order their work by it without the host: the simulation's submission
//! signals the step it finished, the drawing's waits for it, and the
//! simulation's next copy into the drawn blades waits for the drawing.

use std::cell::Cell;

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::owned::Owned;
use crate::gpu::Gpu;

pub struct Timeline {
    raw: Owned<vk::Semaphore>,
    /// The value the last submission that signals it was given (0: none
    /// yet; the semaphore starts at 0, so a wait for 0 is already met).
    signalled: Cell<u64>,
}

impl Timeline {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = gpu.device();
        if !device.adapter.info.timeline_semaphores {
            return Err(Error::FeatureMissing {
                device: device.adapter.info.name.clone(),
                feature: "timelineSemaphore (to run the simulation beside the drawing; set render.overlap = \"off\")".into(),
            });
        }
        let mut kind = vk::SemaphoreTypeCreateInfo::default()
            .semaphore_type(vk::SemaphoreType::TIMELINE)
            .initial_value(0);
        let info = vk::SemaphoreCreateInfo::default().push_next(&mut kind);
        // SAFETY: a valid create info on a live device with the
        // timelineSemaphore feature enabled (checked above).
        let raw = unsafe { device.raw.create_semaphore(&info, None) }
            .vk_context("vkCreateSemaphore", name)?;
        Ok(Self {
            raw: Owned::new(device, raw, name),
            signalled: Cell::new(0),
        })
    }

    /// The signal the next submission makes (the value after the last),
    /// once its commands up to `stage` are done. The value counts as
    /// signalled from here: submit the returned info or drop the timeline.
    pub fn signal_next(&self, stage: vk::PipelineStageFlags2) -> vk::SemaphoreSubmitInfo<'static> {
        let value = self.signalled.get() + 1;
        self.signalled.set(value);
        vk::SemaphoreSubmitInfo::default()
            .semaphore(self.raw.raw())
            .value(value)
            .stage_mask(stage)
    }

    /// A wait for the last value signalled, before the waiting
    /// submission's commands at `stage`; None before any signal.
    pub fn wait_last(
        &self,
        stage: vk::PipelineStageFlags2,
    ) -> Option<vk::SemaphoreSubmitInfo<'static>> {
        let value = self.signalled.get();
        (value > 0).then(|| {
            vk::SemaphoreSubmitInfo::default()
                .semaphore(self.raw.raw())
                .value(value)
                .stage_mask(stage)
        })
    }
}
