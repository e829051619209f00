//! The Vulkan loader, the instance, and the validation layer's debug
//! messenger, which counts what the layer reports.

use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::vk;

use crate::error::{Error, Result, VkResultExt};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// What the validation layer is asked to check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ValidationOptions {
    /// Load `VK_LAYER_KHRONOS_validation` and count what it reports.
    pub enabled: bool,
    /// Synchronization validation (hazards between commands).
    pub synchronization: bool,
    /// Best-practices advice (reported as warnings).
    pub best_practices: bool,
}

impl ValidationOptions {
    /// Core checks plus synchronization validation: what every test runs with.
    pub fn strict() -> Self {
        Self {
            enabled: true,
            synchronization: true,
            best_practices: false,
        }
    }

    pub fn off() -> Self {
        Self::default()
    }
}

/// One distinct message ID and how often it came.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ValidationMessage {
    pub id: String,
    pub severity: &'static str,
    pub count: u64,
    pub first_text: String,
}

/// Counts of what the validation layer said, by severity and by message ID.
/// The layer stops repeating one message after 10, so `distinct` matters as
/// much as the totals.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ValidationReport {
    pub enabled: bool,
    pub errors: u64,
    pub warnings: u64,
    pub messages: Vec<ValidationMessage>,
    /// General messages (not validation or performance ones): what the
    /// driver or loader says of its own results, e.g. Mesa naming the
    /// source line behind a VK_ERROR_OUT_OF_DEVICE_MEMORY it returns. The
    /// failed call already reports the error; these are kept, not counted.
    pub driver_messages: Vec<ValidationMessage>,
}

impl ValidationReport {
    pub fn distinct_errors(&self) -> usize {
        self.messages
            .iter()
            .filter(|m| m.severity == "error")
            .count()
    }

    /// `Err` when any error was reported, naming the first.
    pub fn check(&self) -> Result<()> {
        if self.errors == 0 {
            return Ok(());
        }
        let first = self
            .messages
            .iter()
            .find(|m| m.severity == "error")
            .map(|m| format!("{}: {}", m.id, m.first_text))
            .unwrap_or_default();
        Err(Error::Validation {
            errors: self.errors,
            distinct: self.distinct_errors(),
            first,
        })
    }
}

/// Shared with the debug callback through its user-data pointer, and with
/// `Gpu`, which reads it after the instance is gone.
#[derive(Default)]
pub(super) struct MessageLog {
    report: Mutex<ValidationReport>,
    echo: bool,
}

impl MessageLog {
    /// What the layer has reported so far.
    pub(super) fn report(&self) -> ValidationReport {
        self.report
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }
}

/// The loader, the instance and (with validation) the debug messenger,
/// destroyed in `Drop` (after the device, which holds an `Arc` of it).
pub struct Instance {
    pub(super) entry: ash::Entry,
    pub(super) raw: ash::Instance,
    pub(super) debug_utils: Option<ash::ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    // In an Arc so its address is stable: the messenger holds a raw pointer
    // to it until `drop`, and `Gpu` reads it after that.
    pub(super) log: Arc<MessageLog>,
}

impl Instance {
    /// With `window_extensions` (`gpu::surface::window_extensions`) the
    /// instance can make surfaces for a window; empty for offscreen work.
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn new(validation: ValidationOptions, window_extensions: &[&'static CStr]) -> Result<Self> {
        // SAFETY: loading libvulkan runs its initialisers; we trust the system's loader.
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| Error::LoaderMissing(e.to_string()))?;

        // SAFETY: a plain query on a loaded entry.
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .vk_context("vkEnumerateInstanceLayerProperties", "instance layers")?;
        // SAFETY: as above.
        let extensions = unsafe { entry.enumerate_instance_extension_properties(None) }
            .vk_context(
                "vkEnumerateInstanceExtensionProperties",
                "instance extensions",
            )?;
        let has_layer = layers
            .iter()
            .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        if validation.enabled && !has_layer {
            return Err(Error::ValidationLayerMissing);
        }
        // The validation layer brings debug utils itself; without it the
        // loader or driver may still offer it for object names.
        let has_debug_utils = validation.enabled
            || extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::debug_utils::NAME));

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"meadow")
            .application_version(1)
            .engine_name(c"meadow")
            .api_version(vk::API_VERSION_1_3);
        let layer_ptrs: Vec<*const i8> = if validation.enabled {
            vec![VALIDATION_LAYER.as_ptr()]
        } else {
            vec![]
        };
        let mut ext_ptrs: Vec<*const i8> = if has_debug_utils {
            vec![ash::ext::debug_utils::NAME.as_ptr()]
        } else {
            vec![]
        };
        for wanted in window_extensions {
            if !extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(*wanted))
            {
                return Err(Error::FeatureMissing {
                    device: "the Vulkan loader".into(),
                    feature: format!("{} (to show a window)", wanted.to_string_lossy()),
                });
            }
            ext_ptrs.push(wanted.as_ptr());
        }

        let log = Arc::new(MessageLog {
            report: Mutex::new(ValidationReport {
                enabled: validation.enabled,
                ..Default::default()
            }),
            echo: std::env::var_os("MEADOW_QUIET_VALIDATION").is_none(),
        });
        let mut enabled_features = Vec::new();
        if validation.synchronization {
            enabled_features.push(vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION);
        }
        if validation.best_practices {
            enabled_features.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES);
        }
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        let mut messenger_info = messenger_create_info(&log);

        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layer_ptrs)
            .enabled_extension_names(&ext_ptrs);
        if validation.enabled {
            // Chained so that instance creation and destruction are checked too.
            create_info = create_info
                .push_next(&mut features)
                .push_next(&mut messenger_info);
        }
        // SAFETY: every pointer in create_info lives until this call returns.
        let raw = unsafe { entry.create_instance(&create_info, None) }.map_err(|r| match r {
            // The loader's answer when it finds no driver at all.
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::NoDevice,
            r => Error::vk("vkCreateInstance", "Vulkan 1.3 instance", r),
        })?;

        let debug_utils =
            has_debug_utils.then(|| ash::ext::debug_utils::Instance::new(&entry, &raw));
        let messenger = match (&debug_utils, validation.enabled) {
            (Some(du), true) => {
                // SAFETY: the user-data pointer targets `log`, held by the
                // returned Instance, which destroys the messenger first.
                match unsafe { du.create_debug_utils_messenger(&messenger_create_info(&log), None) }
                {
                    Ok(m) => m,
                    Err(r) => {
                        // SAFETY: nothing was created from this instance yet.
                        unsafe { raw.destroy_instance(None) };
                        return Err(Error::vk(
                            "vkCreateDebugUtilsMessengerEXT",
                            "validation messenger",
                            r,
                        ));
                    }
                }
            }
            _ => vk::DebugUtilsMessengerEXT::null(),
        };

        Ok(Self {
            entry,
            raw,
            debug_utils,
            messenger,
            log,
        })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if let Some(du) = &self.debug_utils {
            if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                // SAFETY: made from this instance in `new`, destroyed once.
                unsafe { du.destroy_debug_utils_messenger(self.messenger, None) };
            }
        }
        // SAFETY: the device and every object made from this instance are
        // gone: each holds an Arc of the instance, and this is the last.
        unsafe { self.raw.destroy_instance(None) };
    }
}

fn messenger_create_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(log as *const MessageLog as *mut c_void)
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: `user` is the `MessageLog` the Instance owns for the
    // messenger's whole life; `data` is valid for this call (Vulkan spec).
    let (log, data) = unsafe { (&*(user as *const MessageLog), &*data) };
    // SAFETY: `data` is valid for this call, its strings NUL-terminated.
    let text = unsafe { data.message_as_c_str() }
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    // SAFETY: as above.
    let id = unsafe { data.message_id_name_as_c_str() }
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| format!("id {:#x}", data.message_id_number));
    let severity_name = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        "error"
    } else {
        "warning"
    };
    // The layer's findings come as validation or performance messages;
    // a general one is the driver or loader speaking of itself.
    let from_layer = types.intersects(
        vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
            | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
    );
    if log.echo {
        let source = if from_layer { "validation" } else { "driver" };
        eprintln!("{source} {severity_name}: {text}");
    }
    let Ok(mut report) = log.report.lock() else {
        return vk::FALSE;
    };
    let report = &mut *report;
    let messages = if from_layer {
        match severity_name {
            "error" => report.errors += 1,
            _ => report.warnings += 1,
        }
        &mut report.messages
    } else {
        &mut report.driver_messages
    };
    match messages
        .iter_mut()
        .find(|m| m.severity == severity_name && m.id == id)
    {
        Some(m) => m.count += 1,
        None => messages.push(ValidationMessage {
            id,
            severity: severity_name,
            count: 1,
            first_text: text,
        }),
    }
    vk::FALSE
}
