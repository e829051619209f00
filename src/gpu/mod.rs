//! Thin, explicit Vulkan: the instance, the device, memory, buffers, images,
//! shader modules, command submission and GPU queries. `Gpu` bundles the
//! long-lived objects and tears them down in the right order.

pub mod buffer;
pub mod commands;
pub mod descriptors;
pub mod device;
pub mod fault;
pub mod image;
pub mod instance;
pub mod memory;
pub mod shader;
pub mod timing;

pub use buffer::Buffer;
pub use device::{Device, DeviceInfo};
pub use fault::FaultPlan;
pub use image::{Image, ImageDesc};
pub use instance::{Instance, ValidationOptions, ValidationReport};
pub use memory::{Memory, MemoryLocation};

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
}

/// The instance, the device and its memory: everything a frame needs that
/// lives as long as the program.
pub struct Gpu {
    pub memory: Memory,
    pub device: Device,
    pub instance: Instance,
    memory_budget: Option<u64>,
    pub(crate) faults: fault::Faults,
}

impl Gpu {
    pub fn new(options: &GpuOptions) -> Result<Self> {
        let instance = Instance::new(options.validation)?;
        let opened = device::enumerate(&instance, &options.pretend_missing)
            .and_then(|adapters| device::choose(&adapters, options.device_name.as_deref()))
            .and_then(|adapter| Device::new(&instance, adapter));
        let device = match opened {
            Ok(d) => d,
            Err(e) => {
                instance.destroy();
                return Err(e);
            }
        };
        let memory = match Memory::new(&instance.raw, &device.raw, device.adapter.raw) {
            Ok(m) => m,
            Err(e) => {
                device.destroy();
                instance.destroy();
                return Err(e);
            }
        };
        Ok(Self {
            memory,
            device,
            instance,
            memory_budget: options.memory_budget,
            faults: fault::Faults::new(options.faults),
        })
    }

    /// Every device on this machine, for `meadow devices`, and what
    /// validation said of the instance.
    pub fn list_devices(options: &GpuOptions) -> Result<(Vec<DeviceInfo>, ValidationReport)> {
        let instance = Instance::new(options.validation)?;
        let adapters = device::enumerate(&instance, &options.pretend_missing);
        let report = instance.destroy();
        Ok((adapters?.into_iter().map(|a| a.info).collect(), report))
    }

    pub fn info(&self) -> &DeviceInfo {
        &self.device.adapter.info
    }

    /// Size of the largest device-local memory heap, in bytes.
    pub fn device_local_bytes(&self) -> u64 {
        // SAFETY: a plain query on this instance's physical device.
        let props = unsafe {
            self.instance
                .raw
                .get_physical_device_memory_properties(self.device.adapter.raw)
        };
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

    /// Device memory for `name`: every buffer and image allocates here.
    pub fn allocate(
        &self,
        name: &str,
        requirements: ash::vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<gpu_allocator::vulkan::Allocation> {
        self.faults.allocation(name)?;
        self.memory.allocate(name, requirements, location, linear)
    }

    pub fn wait_idle(&self) {
        // SAFETY: a live device; failure (device lost) leaves nothing to wait for.
        let _ = unsafe { self.device.raw.device_wait_idle() };
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

    /// Tears down in order: allocator, device, messenger, instance. Returns
    /// what validation reported over the whole life, leaks at device
    /// destruction included; live allocations count as errors.
    pub fn destroy(self) -> ValidationReport {
        self.wait_idle();
        let leaked = self.memory.live_allocations();
        self.memory.destroy();
        self.device.destroy();
        let mut report = self.instance.destroy();
        if !leaked.is_empty() {
            report.errors += leaked.len() as u64;
            report.messages.push(instance::ValidationMessage {
                id: "meadow-leaked-allocation".into(),
                severity: "error",
                count: leaked.len() as u64,
                first_text: format!("GPU allocations alive at teardown: {}", leaked.join(", ")),
            });
        }
        report
    }
}
