//! A window's Vulkan surface (VK_KHR_surface and the window system's own
//! extension, through ash-window), destroyed in `Drop` before the instance
//! it was made from.

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::device::Device;
use crate::gpu::Gpu;

/// The instance extensions a surface on `display` needs, for
/// `GpuOptions::window_extensions`.
pub fn window_extensions(display: RawDisplayHandle) -> Result<Vec<&'static CStr>> {
    let names = ash_window::enumerate_required_extensions(display).map_err(|_| {
        Error::InvalidInput(format!(
            "Vulkan cannot show a window on this display ({display:?}); use `meadow render` instead"
        ))
    })?;
    Ok(names
        .iter()
        // SAFETY: ash-window returns pointers to ash's static, NUL-terminated
        // extension names.
        .map(|&p| unsafe { CStr::from_ptr(p) })
        .collect())
}

pub struct Surface {
    // Holds the device, and so the instance, alive until the surface goes.
    device: Arc<Device>,
    pub(super) loader: ash::khr::surface::Instance,
    pub(super) raw: vk::SurfaceKHR,
}

impl Surface {
    /// A surface on `window`; refused when the device's queue cannot
    /// present to it.
    pub fn new(gpu: &Gpu, display: RawDisplayHandle, window: RawWindowHandle) -> Result<Self> {
        let device = gpu.device().clone();
        let instance = &device.instance;
        let loader = ash::khr::surface::Instance::new(&instance.entry, &instance.raw);
        // SAFETY: the handles come from a live winit window that outlives
        // this surface (the viewer drops the surface first); the instance
        // was made with the extensions `window_extensions` named.
        let raw = unsafe {
            ash_window::create_surface(&instance.entry, &instance.raw, display, window, None)
        }
        .vk_context("vkCreate*SurfaceKHR", "window surface")?;
        let surface = Self {
            device,
            loader,
            raw,
        };
        // SAFETY: a plain query on this instance's physical device and surface.
        let supported = unsafe {
            surface.loader.get_physical_device_surface_support(
                surface.device.adapter.raw,
                surface.device.queue_family,
                surface.raw,
            )
        }
        .vk_context("vkGetPhysicalDeviceSurfaceSupportKHR", "window surface")?;
        if !supported {
            return Err(Error::FeatureMissing {
                device: surface.device.adapter.info.name.clone(),
                feature: "presentation to this window from its graphics queue".into(),
            });
        }
        Ok(surface)
    }

    pub(super) fn device(&self) -> &Arc<Device> {
        &self.device
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: made from this instance; the swapchains made on it hold
        // the surface borrowed and are gone (`Swapchain` cannot outlive it).
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}
