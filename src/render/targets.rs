//! Offscreen render targets: multisampled colour and depth, the single-
//! sample resolve image, and the host buffer the frame is read back into.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::{Buffer, Gpu, Image, ImageDesc, MemoryLocation, TargetFormats};

/// sRGB storage: shaders work in linear light, the PNG gets sRGB bytes.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

pub struct RenderTargets {
    pub extent: vk::Extent2D,
    /// Rendered into: multisampled when samples > 1.
    pub color: Image,
    pub depth: Image,
    /// The single-sample image the multisampled colour resolves into (None at 1x).
    pub resolve: Option<Image>,
    /// Host-visible RGBA8 copy of the final image.
    pub readback: Buffer,
}

/// The largest sample count the device supports for colour and depth that
/// is not above `requested` (a power of two).
pub fn choose_samples(gpu: &Gpu, requested: u32) -> vk::SampleCountFlags {
    let limits = gpu.limits();
    let supported = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    [64u32, 32, 16, 8, 4, 2, 1]
        .into_iter()
        .filter(|&n| n <= requested)
        .map(vk::SampleCountFlags::from_raw)
        .find(|&s| supported.contains(s))
        .unwrap_or(vk::SampleCountFlags::TYPE_1)
}

impl RenderTargets {
    /// `depth_sampled`: the depth target is kept after the colour pass and
    /// read by compute (the depth pyramid), not transient.
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        samples: vk::SampleCountFlags,
        depth_sampled: bool,
    ) -> Result<Self> {
        let limits = gpu.limits();
        let max = limits
            .max_framebuffer_width
            .min(limits.max_framebuffer_height)
            .min(limits.max_image_dimension2_d);
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::InvalidInput(format!(
                "image size {width}x{height} is not allowed on this device, use 1..={max} in each direction"
            )));
        }
        let extent = vk::Extent2D { width, height };
        let multisampled = samples != vk::SampleCountFlags::TYPE_1;
        let color = Image::new(
            gpu,
            &ImageDesc {
                name: if multisampled {
                    "colour target (multisampled)"
                } else {
                    "colour target"
                },
                format: COLOR_FORMAT,
                extent,
                samples,
                usage: if multisampled {
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
                } else {
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
                },
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
            },
        )?;
        let depth = Image::new(
            gpu,
            &ImageDesc {
                name: "depth target",
                format: DEPTH_FORMAT,
                extent,
                samples,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | if depth_sampled {
                        vk::ImageUsageFlags::SAMPLED
                    } else {
                        vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
                    },
                aspect: vk::ImageAspectFlags::DEPTH,
                mip_levels: 1,
            },
        )?;
        let resolve = multisampled
            .then(|| {
                Image::new(
                    gpu,
                    &ImageDesc {
                        name: "colour resolve target",
                        format: COLOR_FORMAT,
                        extent,
                        samples: vk::SampleCountFlags::TYPE_1,
                        usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                            | vk::ImageUsageFlags::TRANSFER_SRC,
                        aspect: vk::ImageAspectFlags::COLOR,
                        mip_levels: 1,
                    },
                )
            })
            .transpose()?;
        let readback = Buffer::new(
            gpu,
            "frame readback",
            width as u64 * height as u64 * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            extent,
            color,
            depth,
            resolve,
            readback,
        })
    }

    pub fn formats(&self) -> TargetFormats {
        TargetFormats {
            color: Some(COLOR_FORMAT),
            depth: DEPTH_FORMAT,
            samples: self.color.samples,
        }
    }

    /// The single-sample image holding the final frame.
    pub fn final_image(&self) -> &Image {
        self.resolve.as_ref().unwrap_or(&self.color)
    }
}
