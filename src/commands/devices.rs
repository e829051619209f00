//! `meadow devices`: every Vulkan device on this machine, whether it can
//! run meadow (and if not, what it lacks), one line each.

use crate::error::Result;
use crate::gpu::{DeviceInfo, Gpu, GpuOptions, ValidationReport};

/// The devices and what validation said of the instance.
pub fn devices(options: &GpuOptions) -> Result<(Vec<DeviceInfo>, ValidationReport)> {
    Gpu::list_devices(options)
}

/// One line for a device.
pub fn line(d: &DeviceInfo) -> String {
    format!(
        "{}  [{}]  Vulkan {}  {}  max MSAA {}x  {}  {}",
        d.name,
        d.device_type,
        d.api_version,
        d.driver,
        d.max_msaa,
        // The simulation beside the drawing needs a second queue of the
        // graphics family and timeline semaphores (render.overlap).
        match d.queues {
            q if d.has_simulation_queue() => {
                format!("{q} graphics queues (steps beside the drawing)")
            }
            q => format!("{q} graphics queue{}", if q == 1 { "" } else { "s" }),
        },
        match &d.missing {
            None => "qualifies".to_string(),
            Some(f) => format!("does not qualify: lacks {f}"),
        }
    )
}
