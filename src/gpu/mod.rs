//! Thin, explicit Vulkan, and the only place meadow calls it: the
//! instance, the device, memory, buffers, images, samplers, pipelines,
//! descriptor sets, command recording with named barrier presets, and GPU
//! queries. Every object holds an `Arc` of the device and releases itself
//! in `Drop`; nothing above this module sees a raw handle or writes
//! `unsafe`. It knows nothing of grass or wind.

pub mod barrier;
pub mod batches;
pub mod buffer;
pub mod command_pool;
pub mod depends_on;
pub mod descriptors;
pub mod device;
pub mod fault;
pub mod image;
pub mod instance;
pub mod journal;
mod made_once;
pub mod memory;
pub mod overlay;
pub mod owned;
pub mod pipeline;
pub mod query;
pub mod recording;
pub mod shader;
pub mod surface;
pub mod swapchain;
pub mod sync;
pub mod timeline;

use std::sync::Arc;

use made_once::MadeOnce;

pub use barrier::Access;
pub use batches::{part, sets_per_batch};
pub use buffer::Buffer;
pub use command_pool::CommandPool;
pub use depends_on::DependsOn;
pub use descriptors::{Bound, DescriptorKind, DescriptorSet, LayoutBinding, PipelineLayout};
pub use device::{Device, DeviceInfo};
pub use fault::FaultPlan;
pub use image::{Image, ImageDesc};
pub use instance::{Instance, ValidationOptions, ValidationReport};
pub use memory::{DeviceMemory, MemoryLocation};
pub use overlay::{OverlayDraw, OverlayRenderer};
pub use owned::Sampler;
pub use pipeline::{GraphicsDesc, Pipeline, TargetFormats};
pub use recording::{Attachments, Dispatches, Recording};
pub use shader::{kernels_set, BindingAccess, ShaderBinding};
pub use surface::Surface;
pub use swapchain::Swapchain;
pub use sync::{BufferId, BufferUse, ImageUse};
pub use timeline::Timeline;

use crate::error::Result;

const MIB: f64 = (1u64 << 20) as f64;

/// How to open the GPU.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    pub validation: ValidationOptions,
    /// Pick the first device whose name contains this (case-insensitive).
    pub device_name: Option<String>,
    /// Treat these features as absent (tests of the refusal and fallback
    /// paths): a required one such as "tessellationShader" makes the device
    /// unusable; the optional "timestamps" and "pipelineStatisticsQuery"
    /// make timings and statistics report as unavailable. Also read from
    /// MEADOW_PRETEND_MISSING (comma-separated) by the binary.
    pub pretend_missing: Vec<String>,
    /// The most device memory (bytes) one piece of work may ask for; the
    /// default is half the largest device-local heap. For sharing a GPU, and
    /// for testing the refusal without a huge allocation.
    pub memory_budget: Option<u64>,
    /// Failures to inject (tests of the out-of-memory and device-loss
    /// paths); none by default.
    pub faults: FaultPlan,
    /// The most bytes one storage binding may reach, when below the
    /// device's maxStorageBufferRange: tests of the kernels that run in
    /// batches (`gpu::batches`) on a few thousand blades instead of
    /// millions.
    pub storage_range: Option<u32>,
    /// The instance extensions a window's surface needs
    /// (`surface::window_extensions`); with any, the device can present.
    /// Empty for offscreen work.
    pub window_extensions: Vec<&'static std::ffi::CStr>,
}

/// The open GPU: the device (which holds the instance) and what the
/// validation layer has said. Objects made through it hold the device
/// alive; `finish` tears it down and reports any still alive as leaks.
pub struct Gpu {
    device: Arc<Device>,
    log: Arc<instance::MessageLog>,
    memory_budget: Option<u64>,
    /// The layouts and compute pipelines made so far, shared by every
    /// pass made on this GPU (`PipelineLayout::new`,
    /// `Pipeline::compute_specialized`).
    layouts: MadeOnce<descriptors::LayoutKey, Arc<PipelineLayout>>,
    compute: MadeOnce<pipeline::ComputeKey, Pipeline>,
}

impl Gpu {
    pub fn new(options: &GpuOptions) -> Result<Self> {
        let instance = Arc::new(Instance::new(
            options.validation,
            &options.window_extensions,
        )?);
        let log = instance.log.clone();
        let mut adapter = device::enumerate(&instance, &options.pretend_missing)
            .and_then(|adapters| device::choose(&adapters, options.device_name.as_deref()))?;
        if let Some(range) = options.storage_range {
            let limits = &mut adapter.properties.limits;
            limits.max_storage_buffer_range = limits.max_storage_buffer_range.min(range);
        }
        let presents = !options.window_extensions.is_empty();
        let device = Device::new(
            instance,
            adapter,
            fault::Faults::new(options.faults),
            presents,
        )?;
        Ok(Self {
            device,
            log,
            memory_budget: options.memory_budget,
            layouts: MadeOnce::default(),
            compute: MadeOnce::default(),
        })
    }

    /// Every device on this machine, for `meadow devices`, and what
    /// validation said of the instance.
    pub fn list_devices(options: &GpuOptions) -> Result<(Vec<DeviceInfo>, ValidationReport)> {
        let instance = Instance::new(options.validation, &[])?;
        let adapters = device::enumerate(&instance, &options.pretend_missing);
        let log = instance.log.clone();
        drop(instance);
        Ok((
            adapters?.into_iter().map(|a| a.info).collect(),
            log.report(),
        ))
    }

    pub fn info(&self) -> &DeviceInfo {
        &self.device.adapter.info
    }

    /// Whether a second queue runs work beside the main one
    /// (`CommandPool::on_simulation_queue`).
    pub fn has_simulation_queue(&self) -> bool {
        self.device.compute_queue.is_some()
    }

    /// The device, for the objects made from it.
    pub(crate) fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// How many distinct compute pipelines this GPU has made.
    pub fn compute_pipelines_made(&self) -> usize {
        self.compute.count()
    }

    pub fn limits(&self) -> &ash::vk::PhysicalDeviceLimits {
        self.device.limits()
    }

    /// Size of the largest device-local memory heap, in bytes.
    pub fn device_local_bytes(&self) -> u64 {
        let instance = &self.device.instance.raw;
        // SAFETY: a plain query on this instance's physical device.
        let props =
            unsafe { instance.get_physical_device_memory_properties(self.device.adapter.raw) };
        props.memory_heaps[..props.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(ash::vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0)
    }

    /// Refuses up front work that cannot fit in device memory: more than
    /// the budget, by default half the largest device-local heap (the rest
    /// is left to the render targets, the shadow map and other programs).
    pub fn check_fits(&self, what: &str, bytes: u64) -> Result<()> {
        let heap = self.device_local_bytes();
        let (budget, whose) = match self.memory_budget {
            Some(b) => (b, "the --gpu-memory-mib budget".to_string()),
            None => (heap / 2, format!("half of the device's {} MiB", heap >> 20)),
        };
        if bytes > budget {
            return Err(crate::Error::WouldNotFit(format!(
                "{what} needs {:.1} MiB of GPU memory, more than {whose} ({:.1} MiB); make it smaller",
                bytes as f64 / MIB,
                budget as f64 / MIB
            )));
        }
        Ok(())
    }

    /// The device memory the run's allocations hold now and at most so
    /// far (report.json's and every report's `device_memory`).
    pub fn device_memory(&self) -> DeviceMemory {
        self.device.memory.usage()
    }

    pub fn wait_idle(&self) {
        self.device.wait_idle();
    }

    /// Tears the GPU down after `work` and pairs its result with what
    /// validation reported. When the work failed and validation reported
    /// errors too (a failure path that leaked objects, say), the error
    /// names both: a broken failure path must not go unseen.
    pub fn finish<T>(self, work: Result<T>) -> Result<(T, ValidationReport)> {
        let report = self.destroy();
        match (work, report.check()) {
            (Ok(value), _) => Ok((value, report)),
            (Err(e), Ok(())) => Err(e),
            (Err(e), Err(validation)) => Err(crate::Error::AlsoInvalid {
                cause: Box::new(e),
                validation: Box::new(validation),
            }),
        }
    }

    /// Tears down: the device (its allocator first), then the messenger and
    /// the instance. Returns what validation reported over the whole life,
    /// leaks at device destruction included. GPU objects or allocations
    /// still alive here count as errors: their owner forgot them, and the
    /// device stays until the last of them is dropped.
    pub fn destroy(self) -> ValidationReport {
        self.device.wait_idle();
        // What is kept for sharing is not alive for any owner.
        self.compute.clear();
        self.layouts.clear();
        let leaked_allocations = self.device.memory.live_allocations();
        let leaked_objects = Arc::strong_count(&self.device) - 1;
        let Self { device, log, .. } = self;
        drop(device);
        let mut report = log.report();
        let mut leak = |id: &str, count: usize, text: String| {
            report.errors += count as u64;
            report.messages.push(instance::ValidationMessage {
                id: id.into(),
                severity: "error",
                count: count as u64,
                first_text: text,
            });
        };
        if !leaked_allocations.is_empty() {
            leak(
                "meadow-leaked-allocation",
                leaked_allocations.len(),
                format!(
                    "GPU allocations alive at teardown: {}",
                    leaked_allocations.join(", ")
                ),
            );
        }
        if leaked_objects > 0 {
            leak(
                "meadow-leaked-object",
                leaked_objects,
                format!("{leaked_objects} GPU object(s) still alive at teardown"),
            );
        }
        report
    }
}
