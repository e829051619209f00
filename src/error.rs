//! The library's one error type. Every message is a single line that names
//! the cause and what to do about it; the binary prints it as it is.

use ash::vk;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("no Vulkan loader (libvulkan.so.1) could be loaded: {0}; run scripts/ensure-vulkan or install libvulkan1 and mesa-vulkan-drivers")]
    LoaderMissing(String),

    #[error("no Vulkan device found; run scripts/ensure-vulkan or install mesa-vulkan-drivers for the lavapipe CPU driver")]
    NoDevice,

    #[error("no Vulkan device name contains {0:?}; `meadow devices` lists the devices")]
    DeviceNotFound(String),

    #[error("device {device:?} lacks {feature}, which meadow's pipeline needs; pick another with --device (`meadow devices` lists them)")]
    FeatureMissing { device: String, feature: String },

    #[error("the Khronos validation layer is not installed; install vulkan-validationlayers (scripts/ensure-vulkan does) or run without --validation")]
    ValidationLayerMissing,

    #[error("out of GPU memory while creating {what}; use fewer blades or a smaller image")]
    OutOfDeviceMemory { what: String },

    /// Refused before allocating: the estimate is over the memory budget.
    #[error("{0}")]
    WouldNotFit(String),

    #[error("out of host memory while creating {what}; use fewer blades or a smaller image")]
    OutOfHostMemory { what: String },

    #[error("the Vulkan device was lost (VK_ERROR_DEVICE_LOST) during {during}; the driver reset or crashed: run again, and update the driver if it keeps happening")]
    DeviceLost { during: String },

    #[error("Vulkan call {call} failed with {result:?}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },

    #[error("GPU memory allocation for {what} failed: {source}")]
    Allocation {
        what: String,
        #[source]
        source: gpu_allocator::AllocationError,
    },

    #[error("{0}")]
    InvalidInput(String),

    #[error("{path}: {source}{}", io_advice(.source))]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },

    #[error("encoding {path} failed: {source}")]
    Image {
        path: String,
        #[source]
        source: image::ImageError,
    },

    /// A failure after which validation reported errors as well.
    #[error("{cause}; and {validation}")]
    AlsoInvalid {
        cause: Box<Error>,
        validation: Box<Error>,
    },

    #[error("validation reported {errors} error(s) ({distinct} distinct message IDs); the first: {first}")]
    Validation {
        errors: u64,
        distinct: usize,
        first: String,
    },
}

/// What to do about a write that failed for want of room.
fn io_advice(e: &std::io::Error) -> &'static str {
    match e.kind() {
        std::io::ErrorKind::StorageFull | std::io::ErrorKind::QuotaExceeded => {
            "; free some space or pass --out a folder on another disk (the files already written are complete)"
        }
        std::io::ErrorKind::FileTooLarge => "; pass --out a folder on a disk that allows larger files",
        _ => "",
    }
}

impl Error {
    /// Maps a failed Vulkan call to an error by the result's name: memory
    /// exhaustion, device loss and missing features get their own variants.
    pub fn vk(call: &'static str, what: impl Into<String>, result: vk::Result) -> Self {
        let what = what.into();
        match result {
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => Error::OutOfDeviceMemory { what },
            vk::Result::ERROR_OUT_OF_HOST_MEMORY => Error::OutOfHostMemory { what },
            vk::Result::ERROR_DEVICE_LOST => Error::DeviceLost { during: what },
            vk::Result::ERROR_FEATURE_NOT_PRESENT | vk::Result::ERROR_EXTENSION_NOT_PRESENT => {
                Error::FeatureMissing {
                    device: String::from("(selected device)"),
                    feature: format!("what {call} asked for ({what})"),
                }
            }
            result => Error::Vulkan { call, result },
        }
    }

    /// Maps a gpu-allocator failure, keeping out-of-memory recognisable.
    pub fn alloc(what: impl Into<String>, source: gpu_allocator::AllocationError) -> Self {
        let what = what.into();
        match source {
            gpu_allocator::AllocationError::OutOfMemory => Error::OutOfDeviceMemory { what },
            source => Error::Allocation { what, source },
        }
    }

    pub fn io(path: impl AsRef<std::path::Path>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            source,
        }
    }

    /// An image encoder's failure: a failed write (a full disk while a GIF
    /// streams out) is an I/O error with its advice, anything else an
    /// encoding error.
    pub fn image(path: impl AsRef<std::path::Path>, source: image::ImageError) -> Self {
        match source {
            image::ImageError::IoError(e) => Error::io(path, e),
            source => Error::Image {
                path: path.as_ref().display().to_string(),
                source,
            },
        }
    }
}

/// An empty vector with room for `len` items (one per blade, a count the
/// user chooses), failing with `OutOfHostMemory` instead of aborting the
/// process when the machine cannot hold them.
pub fn try_with_capacity<T>(len: usize, what: &str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| Error::OutOfHostMemory {
            what: format!(
                "{what} ({:.1} MiB)",
                len as f64 * std::mem::size_of::<T>() as f64 / (1u64 << 20) as f64
            ),
        })?;
    Ok(v)
}

/// `try_with_capacity(len)` filled from `items` (at most `len` of them).
pub fn try_collect<T>(
    len: usize,
    items: impl IntoIterator<Item = T>,
    what: &str,
) -> Result<Vec<T>> {
    let mut v = try_with_capacity(len, what)?;
    v.extend(items.into_iter().take(len));
    Ok(v)
}

/// `result.vk_context("vkCreateBuffer", "blade vertex buffer")?`
pub trait VkResultExt<T> {
    fn vk_context(self, call: &'static str, what: &str) -> Result<T>;
}

impl<T> VkResultExt<T> for std::result::Result<T, vk::Result> {
    fn vk_context(self, call: &'static str, what: &str) -> Result<T> {
        self.map_err(|r| Error::vk(call, what, r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed Vulkan call is mapped by its result's name, so a real
    /// device loss or memory exhaustion anywhere reads like the injected
    /// ones the fault tests walk.
    #[test]
    fn vulkan_results_map_by_name() {
        let e = Error::vk(
            "vkQueueSubmit2",
            "rendering a frame",
            vk::Result::ERROR_DEVICE_LOST,
        );
        assert!(matches!(e, Error::DeviceLost { .. }));
        assert!(e
            .to_string()
            .contains("lost (VK_ERROR_DEVICE_LOST) during rendering a frame"));
        let e = Error::vk(
            "vkAllocateMemory",
            "shadow map",
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        );
        assert_eq!(
            e.to_string(),
            "out of GPU memory while creating shadow map; use fewer blades or a smaller image"
        );
        let e = Error::vk("vkCreateBuffer", "x", vk::Result::ERROR_OUT_OF_HOST_MEMORY);
        assert!(matches!(e, Error::OutOfHostMemory { .. }));
        let e = Error::alloc("grass", gpu_allocator::AllocationError::OutOfMemory);
        assert!(matches!(e, Error::OutOfDeviceMemory { .. }));
    }

    #[test]
    fn a_full_disk_says_what_to_do() {
        let full = std::io::Error::from(std::io::ErrorKind::StorageFull);
        let e = Error::io("out/frame_0003.png", full).to_string();
        assert!(e.starts_with("out/frame_0003.png: "), "{e}");
        assert!(
            e.ends_with("(the files already written are complete)"),
            "{e}"
        );
        let other = std::io::Error::from(std::io::ErrorKind::NotFound);
        assert!(!Error::io("x", other)
            .to_string()
            .contains("free some space"));
        // A full disk under an image encoder (a GIF streaming out) says the same.
        let full = std::io::Error::from(std::io::ErrorKind::StorageFull);
        let e = Error::image("out/animation.gif", image::ImageError::IoError(full)).to_string();
        assert!(
            e.starts_with("out/animation.gif: ") && e.contains("free some space"),
            "{e}"
        );
    }

    #[test]
    fn per_blade_arrays_too_big_for_the_machine_are_an_error() {
        let e = try_with_capacity::<[u8; 64]>(usize::MAX / 64, "the test's blades").unwrap_err();
        assert!(matches!(e, Error::OutOfHostMemory { .. }), "{e}");
        assert!(e.to_string().contains("the test's blades"), "{e}");
        assert_eq!(try_collect(3, 0..10, "three").unwrap(), [0, 1, 2]);
    }
}
