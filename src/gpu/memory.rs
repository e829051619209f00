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

pub struct Memory {
    allocator: Mutex<Option<Allocator>>,
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
            allocator: Mutex::new(Some(allocator)),
        })
    }

    pub fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<Allocation> {
        let mut guard = self.allocator.lock().unwrap();
        let allocator = guard.as_mut().expect("allocator used after destroy");
        allocator
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| Error::alloc(name, e))
    }

    pub fn free(&self, allocation: Allocation) {
        let mut guard = self.allocator.lock().unwrap();
        if let Some(allocator) = guard.as_mut() {
            // A failed free only means the allocation was not ours; nothing to undo.
            let _ = allocator.free(allocation);
        }
    }

    /// Names of the allocations still alive (a leak, at teardown).
    pub fn live_allocations(&self) -> Vec<String> {
        let guard = self.allocator.lock().unwrap();
        guard
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
        self.allocator.lock().unwrap().take();
    }
}
