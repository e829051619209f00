//! Device memory through gpu-allocator. The allocator lives behind a mutex
//! inside `Gpu` and is dropped before the device; dropping it with live
//! allocations is reported as a leak.

use std::sync::Mutex;

use ash::vk;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
pub use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};

/// The device memory a run's allocations hold: now, and the most at once
/// since the device was opened (bytes of the allocations themselves, not
/// of the blocks the allocator reserves around them; the swapchain's
/// images, which the driver owns, are not counted).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct DeviceMemory {
    pub allocated_bytes: u64,
    pub peak_bytes: u64,
}

struct Allocations {
    allocator: Option<Allocator>,
    usage: DeviceMemory,
}

pub struct Memory {
    allocations: Mutex<Allocations>,
}

impl Memory {
    pub fn new(
        instance: &ash::Instance,
        device: &ash::Device,
        physical_device: vk::PhysicalDevice,
    ) -> Result<Self> {
        let mut debug_settings = gpu_allocator::AllocatorDebugSettings::default();
        debug_settings.log_leaks_on_shutdown = true;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings,
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| Error::alloc("the GPU memory allocator", e))?;
        Ok(Self {
            allocations: Mutex::new(Allocations {
                allocator: Some(allocator),
                usage: DeviceMemory::default(),
            }),
        })
    }

    pub fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<Allocation> {
        let mut guard = self.allocations.lock().unwrap();
        let allocations = &mut *guard;
        let allocator = allocations
            .allocator
            .as_mut()
            .expect("allocator used after destroy");
        let allocation = allocator
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| Error::alloc(name, e))?;
        let usage = &mut allocations.usage;
        usage.allocated_bytes += allocation.size();
        usage.peak_bytes = usage.peak_bytes.max(usage.allocated_bytes);
        Ok(allocation)
    }

    pub fn free(&self, allocation: Allocation) {
        let mut guard = self.allocations.lock().unwrap();
        let allocations = &mut *guard;
        if let Some(allocator) = allocations.allocator.as_mut() {
            let size = allocation.size();
            // A failed free only means the allocation was not ours; nothing to undo.
            if allocator.free(allocation).is_ok() {
                let usage = &mut allocations.usage;
                usage.allocated_bytes = usage.allocated_bytes.saturating_sub(size);
            }
        }
    }

    /// The allocations' bytes now and at most so far.
    pub fn usage(&self) -> DeviceMemory {
        self.allocations.lock().unwrap().usage
    }

    /// Names of the allocations still alive (a leak, at teardown).
    pub fn live_allocations(&self) -> Vec<String> {
        let guard = self.allocations.lock().unwrap();
        guard
            .allocator
            .as_ref()
            .map(|a| {
                a.generate_report()
                    .allocations
                    .into_iter()
                    .map(|r| r.name)
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Drops the allocator (freeing its memory blocks). Must run before the
    /// device is destroyed.
    pub fn destroy(&self) {
        self.allocations.lock().unwrap().allocator.take();
    }
}
