//! Physical-device choice and the logical device with the features the
//! paper's pipeline needs (tessellation and geometry shaders).

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::fault::Faults;
use crate::gpu::instance::Instance;
use crate::gpu::memory::{Memory, MemoryLocation};

/// What `meadow devices` shows about one physical device.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DeviceInfo {
    pub name: String,
    pub device_type: String,
    pub api_version: String,
    pub driver: String,
    /// `None` when the device can run meadow, else the first missing feature.
    pub missing: Option<String>,
    /// Largest colour-and-depth MSAA sample count the device offers.
    pub max_msaa: u32,
    pub pipeline_statistics: bool,
    pub timestamps: bool,
    /// Why a timestamp around one draw inside a render pass does not time
    /// that draw on this device (it rasterises the pass's draws when the
    /// pass ends, or per tile); None where it does.
    pub draw_timing_unavailable: Option<String>,
    /// Queues of the graphics+compute family: with two or more, the
    /// simulation runs on a second one beside the drawing
    /// (`render.overlap`, src/frame/ahead.rs).
    pub queues: u32,
    /// Whether the device has timeline semaphores (Vulkan 1.2's
    /// `timelineSemaphore`), which the simulation ahead of the drawing
    /// needs.
    pub timeline_semaphores: bool,
}

impl DeviceInfo {
    /// Whether the device is a CPU (lavapipe): its dispatches cost next to
    /// nothing and its arithmetic all of its time (`type_name_and_rank`'s
    /// name).
    pub fn is_cpu(&self) -> bool {
        self.device_type == "CPU"
    }

    pub fn qualifies(&self) -> bool {
        self.missing.is_none()
    }

    /// Whether the device gets a second queue for the simulation beside
    /// the drawing: two queues of the graphics family, and timeline
    /// semaphores to order them.
    pub fn has_simulation_queue(&self) -> bool {
        self.queues >= 2 && self.timeline_semaphores
    }
}

/// A physical device and what we learnt about it.
#[derive(Clone)]
pub struct Adapter {
    pub raw: vk::PhysicalDevice,
    pub info: DeviceInfo,
    pub properties: vk::PhysicalDeviceProperties,
    pub queue_family: Option<u32>,
    rank: u32,
}

/// Features meadow cannot run without, by the name Vulkan gives them.
/// Devices whose timestamps inside a render pass do not bracket a draw's
/// whole work: llvmpipe runs a draw's vertex, tessellation and geometry
/// stages as it is recorded but rasterises and shades the pass's fragments
/// on its worker threads when the pass ends (the few-bunches grass draw
/// read 4.3 ms of a 91 ms colour pass), and tiling GPUs bin the whole pass
/// before rendering it tile by tile. Whole passes are timed right on both.
fn draw_timing_unavailable(driver: vk::DriverId) -> Option<String> {
    let tiler = [
        vk::DriverId::ARM_PROPRIETARY,
        vk::DriverId::QUALCOMM_PROPRIETARY,
        vk::DriverId::IMAGINATION_PROPRIETARY,
        vk::DriverId::BROADCOM_PROPRIETARY,
        vk::DriverId::SAMSUNG_PROPRIETARY,
        vk::DriverId::MESA_TURNIP,
        vk::DriverId::MESA_PANVK,
        vk::DriverId::MESA_V3DV,
        vk::DriverId::MOLTENVK,
    ];
    if driver == vk::DriverId::MESA_LLVMPIPE {
        Some(
            "llvmpipe rasterises and shades a render pass's fragments when the pass ends, so \
             a timestamp around one draw inside it misses them"
                .into(),
        )
    } else if tiler.contains(&driver) {
        Some("a tiling GPU renders a pass tile by tile after binning all its draws".into())
    } else {
        None
    }
}

fn missing_feature(
    core: &vk::PhysicalDeviceFeatures,
    v13: &vk::PhysicalDeviceVulkan13Features,
    api: u32,
    queue_family: Option<u32>,
    pretend_missing: &[String],
) -> Option<String> {
    let checks: [(&str, bool); 6] = [
        (
            "Vulkan 1.3",
            vk::api_version_major(api) > 1 || vk::api_version_minor(api) >= 3,
        ),
        ("a graphics+compute queue", queue_family.is_some()),
        ("tessellationShader", core.tessellation_shader == vk::TRUE),
        ("geometryShader", core.geometry_shader == vk::TRUE),
        ("dynamicRendering", v13.dynamic_rendering == vk::TRUE),
        ("synchronization2", v13.synchronization2 == vk::TRUE),
    ];
    checks
        .iter()
        .find(|(name, ok)| !ok || pretend_missing.iter().any(|p| p == name))
        .map(|(name, _)| name.to_string())
}

fn type_name_and_rank(t: vk::PhysicalDeviceType) -> (&'static str, u32) {
    // Prefer a discrete GPU, then an integrated one, else a CPU device such as lavapipe.
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => ("discrete GPU", 0),
        vk::PhysicalDeviceType::INTEGRATED_GPU => ("integrated GPU", 1),
        vk::PhysicalDeviceType::VIRTUAL_GPU => ("virtual GPU", 2),
        vk::PhysicalDeviceType::CPU => ("CPU", 3),
        _ => ("other", 4),
    }
}

/// Every physical device, with whether it qualifies.
pub fn enumerate(instance: &Instance, pretend_missing: &[String]) -> Result<Vec<Adapter>> {
    // SAFETY: plain queries on a live instance.
    let raws = unsafe { instance.raw.enumerate_physical_devices() }
        .vk_context("vkEnumeratePhysicalDevices", "device list")?;
    let mut adapters = Vec::new();
    for raw in raws {
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        // SAFETY: queries on a physical device of this live instance; the
        // chained structs live across the calls.
        let (properties, core, families) = unsafe {
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
            instance
                .raw
                .get_physical_device_properties2(raw, &mut props2);
            let properties = props2.properties;
            let mut features2 = vk::PhysicalDeviceFeatures2::default()
                .push_next(&mut v13)
                .push_next(&mut v12);
            instance
                .raw
                .get_physical_device_features2(raw, &mut features2);
            let families = instance
                .raw
                .get_physical_device_queue_family_properties(raw);
            (properties, features2.features, families)
        };
        let queue_family = families
            .iter()
            .position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            })
            .map(|i| i as u32);
        // Optional features: meadow runs without them and says what it
        // cannot report. `pretend_missing` turns them off for tests too.
        let pretend = |name: &str| pretend_missing.iter().any(|p| p == name);
        let timestamps = properties.limits.timestamp_compute_and_graphics == vk::TRUE
            && queue_family.is_some_and(|q| families[q as usize].timestamp_valid_bits > 0)
            && !pretend("timestamps");
        let name = properties
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|_| "(unnamed)".into());
        // SAFETY: Vulkan fills both arrays with NUL-terminated strings.
        let driver_info = unsafe { CStr::from_ptr(driver.driver_info.as_ptr()) }.to_string_lossy();
        // SAFETY: as above.
        let driver_name = unsafe { CStr::from_ptr(driver.driver_name.as_ptr()) }.to_string_lossy();
        let (type_name, rank) = type_name_and_rank(properties.device_type);
        let api = properties.api_version;
        let max_msaa = max_samples(
            properties.limits.framebuffer_color_sample_counts
                & properties.limits.framebuffer_depth_sample_counts,
        );
        let info = DeviceInfo {
            name,
            device_type: type_name.into(),
            api_version: format!(
                "{}.{}.{}",
                vk::api_version_major(api),
                vk::api_version_minor(api),
                vk::api_version_patch(api)
            ),
            driver: format!("{driver_name} {driver_info}").trim().to_string(),
            missing: missing_feature(&core, &v13, api, queue_family, pretend_missing),
            max_msaa,
            pipeline_statistics: core.pipeline_statistics_query == vk::TRUE
                && !pretend("pipelineStatisticsQuery"),
            timestamps,
            draw_timing_unavailable: draw_timing_unavailable(driver.driver_id),
            queues: queue_family.map_or(0, |q| families[q as usize].queue_count),
            timeline_semaphores: v12.timeline_semaphore == vk::TRUE,
        };
        adapters.push(Adapter {
            raw,
            info,
            properties,
            queue_family,
            rank,
        });
    }
    Ok(adapters)
}

fn max_samples(counts: vk::SampleCountFlags) -> u32 {
    [64, 32, 16, 8, 4, 2, 1]
        .into_iter()
        .find(|&n| counts.contains(vk::SampleCountFlags::from_raw(n)))
        .unwrap_or(1)
}

/// Picks the device: by name when `name_filter` is given, else the best-ranked
/// qualifying one. A named device that lacks a feature is refused, naming it.
pub fn choose(adapters: &[Adapter], name_filter: Option<&str>) -> Result<Adapter> {
    if adapters.is_empty() {
        return Err(Error::NoDevice);
    }
    let candidates: Vec<&Adapter> = match name_filter {
        Some(f) => {
            let f = f.to_lowercase();
            let named: Vec<_> = adapters
                .iter()
                .filter(|a| a.info.name.to_lowercase().contains(&f))
                .collect();
            if named.is_empty() {
                return Err(Error::DeviceNotFound(f));
            }
            named
        }
        None => adapters.iter().collect(),
    };
    let best = candidates
        .iter()
        .filter(|a| a.info.qualifies())
        .min_by_key(|a| a.rank)
        .copied();
    match best {
        Some(a) => Ok(a.clone()),
        None => {
            let a = candidates[0];
            Err(Error::FeatureMissing {
                device: a.info.name.clone(),
                feature: a.info.missing.clone().unwrap_or_default(),
            })
        }
    }
}

/// The logical device, its one queue, its memory and the limits read
/// often. Every GPU object holds an `Arc` of it and releases itself in
/// `Drop`, so the device (and, after it, the instance it holds) goes away
/// only when the last object made from it has.
pub struct Device {
    pub(super) raw: ash::Device,
    pub adapter: Adapter,
    pub(super) queue: vk::Queue,
    /// A second queue of the same family, for the simulation beside the
    /// drawing; None where the family has one queue (lavapipe) or the
    /// device lacks timeline semaphores.
    pub(super) compute_queue: Option<vk::Queue>,
    pub queue_family: u32,
    debug_utils: Option<ash::ext::debug_utils::Device>,
    pub pipeline_statistics: bool,
    /// Valid bits of the queue's timestamps (0: none).
    pub timestamp_valid_bits: u32,
    pub(super) memory: Memory,
    pub(super) faults: Faults,
    /// Every object's debug name by its handle (`name`), for the journal
    /// of what recordings do (src/gpu/journal.rs).
    names: std::sync::Mutex<std::collections::HashMap<u64, String>>,
    /// Outlives the device: `Drop` destroys the device before any field goes.
    pub(super) instance: Arc<Instance>,
}

impl Device {
    /// With `presents`, the device can also present to a window's
    /// swapchain (VK_KHR_swapchain).
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub(super) fn new(
        instance: Arc<Instance>,
        adapter: Adapter,
        faults: Faults,
        presents: bool,
    ) -> Result<Arc<Self>> {
        let queue_family = adapter.queue_family.ok_or_else(|| Error::FeatureMissing {
            device: adapter.info.name.clone(),
            feature: "a graphics+compute queue".into(),
        })?;
        // SAFETY: a plain query on a physical device of this instance.
        let families = unsafe {
            instance
                .raw
                .get_physical_device_queue_family_properties(adapter.raw)
        };
        let timestamp_valid_bits = families[queue_family as usize].timestamp_valid_bits;
        // Two queues of the one family where it has them: the second runs
        // the simulation beside the drawing, with no ownership transfers
        // (both queues are of one family).
        let two = adapter.info.has_simulation_queue();
        let priorities = [1.0f32, 1.0];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities[..if two { 2 } else { 1 }])];
        let core = vk::PhysicalDeviceFeatures::default()
            .tessellation_shader(true)
            .geometry_shader(true)
            .pipeline_statistics_query(adapter.info.pipeline_statistics);
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true);
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
            .timeline_semaphore(adapter.info.timeline_semaphores);
        let extensions: Vec<*const i8> = if presents {
            vec![ash::khr::swapchain::NAME.as_ptr()]
        } else {
            vec![]
        };
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&extensions)
            .enabled_features(&core)
            .push_next(&mut v13)
            .push_next(&mut v12);
        // SAFETY: the adapter came from this instance; the create info lives
        // across the call.
        let raw = unsafe { instance.raw.create_device(adapter.raw, &create_info, None) }.map_err(
            |r| match r {
                vk::Result::ERROR_EXTENSION_NOT_PRESENT => Error::FeatureMissing {
                    device: adapter.info.name.clone(),
                    feature: "VK_KHR_swapchain (to show a window)".into(),
                },
                vk::Result::ERROR_FEATURE_NOT_PRESENT => Error::FeatureMissing {
                    device: adapter.info.name.clone(),
                    feature: "tessellationShader/geometryShader/dynamicRendering/synchronization2"
                        .into(),
                },
                r => Error::vk("vkCreateDevice", "logical device", r),
            },
        )?;
        // The allocator is made before the device is wrapped: should it
        // fail, the device is destroyed here, with nothing made from it.
        let memory = match Memory::new(&instance.raw, &raw, adapter.raw) {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: nothing was created from this device yet.
                unsafe { raw.destroy_device(None) };
                return Err(e);
            }
        };
        // SAFETY: the queue family was requested with one queue above.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        // SAFETY: with `two`, the family was requested with two queues.
        let compute_queue = two.then(|| unsafe { raw.get_device_queue(queue_family, 1) });
        let debug_utils = instance
            .debug_utils
            .as_ref()
            .map(|_| ash::ext::debug_utils::Device::new(&instance.raw, &raw));
        let device = Self {
            timestamp_valid_bits,
            pipeline_statistics: adapter.info.pipeline_statistics,
            raw,
            adapter,
            queue,
            compute_queue,
            queue_family,
            debug_utils,
            memory,
            faults,
            names: Default::default(),
            instance,
        };
        device.name(queue, "main queue");
        if let Some(q) = compute_queue {
            device.name(q, "simulation queue (beside the drawing)");
        }
        Ok(Arc::new(device))
    }

    /// Gives a Vulkan object a debug name, so validation messages and
    /// RenderDoc say what it is. A no-op without debug utils.
    pub(super) fn name<H: vk::Handle + Copy>(&self, handle: H, name: &str) {
        let raw = handle.as_raw();
        if let Ok(mut names) = self.names.lock() {
            names.insert(raw, name.to_string());
        }
        let Some(du) = &self.debug_utils else { return };
        let Ok(cname) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&cname);
        // SAFETY: the handle belongs to this device; a naming failure is harmless.
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }

    /// The debug name `name` gave the object of handle `raw` (its handle in
    /// hexadecimal where it was never named).
    pub(super) fn name_of(&self, raw: u64) -> String {
        self.names
            .lock()
            .ok()
            .and_then(|names| names.get(&raw).cloned())
            .unwrap_or_else(|| format!("{raw:#x}"))
    }

    pub fn limits(&self) -> &vk::PhysicalDeviceLimits {
        &self.adapter.properties.limits
    }

    /// Device memory for `name`: every buffer and image allocates here.
    pub(super) fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<Allocation> {
        self.faults.allocation(name)?;
        self.memory.allocate(name, requirements, location, linear)
    }

    /// Waits until the queue has nothing in flight. A failure (device lost)
    /// leaves nothing to wait for.
    pub(super) fn wait_idle(&self) {
        // SAFETY: a live device; external synchronisation of the queue is
        // ours (one thread submits).
        let _ = unsafe { self.raw.device_wait_idle() };
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        self.wait_idle();
        // The allocator frees its memory blocks before the device goes.
        self.memory.destroy();
        // SAFETY: every object made from this device held an Arc of it, so
        // all of them are gone; the queue is idle (above).
        unsafe { self.raw.destroy_device(None) };
    }
}
