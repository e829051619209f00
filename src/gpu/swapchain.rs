//! A window's swapchain, FIFO-presented: acquire an image, blit a frame
//! into it, present it. One frame is in flight at a time (each submission
//! is waited for), so one acquire semaphore serves every frame; each image
//! has its own semaphore for presentation, which may still be waiting on
//! it when the next frame is submitted.

use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::barrier::{image_barrier, Access};
use crate::gpu::device::Device;
use crate::gpu::overlay::{OverlayDraw, OverlayRenderer};
use crate::gpu::owned::Owned;
use crate::gpu::surface::Surface;
use crate::gpu::sync::ImageUse;
use crate::gpu::{Gpu, Image, Recording};

pub struct Swapchain {
    acquired: Owned<vk::Semaphore>,
    rendered: Vec<Owned<vk::Semaphore>>,
    /// One per image, for the overlay's drawing; destroyed in `Drop`
    /// before the swapchain.
    views: Vec<Owned<vk::ImageView>>,
    raw: vk::SwapchainKHR,
    loader: ash::khr::swapchain::Device,
    images: Vec<vk::Image>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    device: Arc<Device>,
    /// Kept alive: `Drop` destroys the swapchain, before any field goes.
    _surface: Arc<Surface>,
}

/// What presenting needs next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    Shown,
    /// The window changed (resized, moved to another screen): make a new
    /// swapchain before the next frame.
    Stale,
}

impl Swapchain {
    /// A swapchain of `surface` at the window's size (`wanted` where the
    /// surface leaves the size to us). Returns None while the window is
    /// minimised (a zero-sized surface has no swapchain).
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn new(
        gpu: &Gpu,
        surface: &Arc<Surface>,
        wanted: vk::Extent2D,
        old: Option<Swapchain>,
    ) -> Result<Option<Self>> {
        let device = gpu.device().clone();
        if !Arc::ptr_eq(surface.device(), &device) {
            return Err(Error::InvalidInput(
                "a swapchain must be made on the device its surface was".into(),
            ));
        }
        let pd = device.adapter.raw;
        // SAFETY: plain queries on this instance's physical device and surface.
        let caps = unsafe {
            surface
                .loader
                .get_physical_device_surface_capabilities(pd, surface.raw)
        }
        .vk_context("vkGetPhysicalDeviceSurfaceCapabilitiesKHR", "swapchain")?;
        // SAFETY: as above.
        let formats = unsafe {
            surface
                .loader
                .get_physical_device_surface_formats(pd, surface.raw)
        }
        .vk_context("vkGetPhysicalDeviceSurfaceFormatsKHR", "swapchain")?;
        let extent = if caps.current_extent.width == u32::MAX {
            vk::Extent2D {
                width: wanted
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: wanted
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        } else {
            caps.current_extent
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST)
        {
            return Err(Error::FeatureMissing {
                device: device.adapter.info.name.clone(),
                feature: "swapchain images that can be blitted into (TRANSFER_DST)".into(),
            });
        }
        // The frame is sRGB-encoded RGBA8; an sRGB swapchain keeps the blit
        // a copy of the same colours whatever the channel order.
        let format = formats
            .iter()
            .find(|f| {
                matches!(
                    f.format,
                    vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
                ) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
            })
            .or(formats.first())
            .copied()
            .ok_or_else(|| Error::FeatureMissing {
                device: device.adapter.info.name.clone(),
                feature: "a surface format for this window".into(),
            })?;
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let loader = ash::khr::swapchain::Device::new(&device.instance.raw, &device.raw);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::COLOR_ATTACHMENT)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            // FIFO: every driver has it, and it never tears.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old.as_ref().map_or(vk::SwapchainKHR::null(), |o| o.raw));
        // SAFETY: a valid create info on a live device; the old swapchain,
        // if any, is retired by this call and destroyed just after.
        let raw = unsafe { loader.create_swapchain(&info, None) }
            .vk_context("vkCreateSwapchainKHR", "swapchain");
        drop(old);
        let raw = raw?;
        device.name(raw, "window swapchain");
        // Owned from here, so a failure below destroys it.
        let mut swapchain = Self {
            acquired: semaphore(&device, "swapchain image acquired")?,
            rendered: Vec::new(),
            views: Vec::new(),
            raw,
            loader,
            images: Vec::new(),
            format: format.format,
            extent,
            device: device.clone(),
            _surface: surface.clone(),
        };
        // SAFETY: the swapchain is live; its images are owned by it.
        swapchain.images = unsafe { swapchain.loader.get_swapchain_images(raw) }
            .vk_context("vkGetSwapchainImagesKHR", "swapchain")?;
        for (i, &image) in swapchain.images.iter().enumerate() {
            device.name(image, &format!("swapchain image {i}"));
            swapchain.rendered.push(semaphore(
                &device,
                &format!("swapchain image {i} rendered"),
            )?);
            swapchain
                .views
                .push(view(&device, image, format.format, i)?);
        }
        Ok(Some(swapchain))
    }

    /// The next image to draw into, or None when the swapchain no longer
    /// fits the window.
    pub fn acquire(&self) -> Result<Option<u32>> {
        // SAFETY: the semaphore is unsignalled: the last frame's submission,
        // which waited on it, has completed.
        let result = unsafe {
            self.loader.acquire_next_image(
                self.raw,
                u64::MAX,
                self.acquired.raw(),
                vk::Fence::null(),
            )
        };
        match result {
            // Suboptimal still acquired (and signals the semaphore): use it.
            Ok((index, _suboptimal)) => Ok(Some(index)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(r) => Err(Error::vk("vkAcquireNextImageKHR", "window swapchain", r)),
        }
    }

    /// Ends `rec` with `frame` (its use declared here: the frame's writes
    /// finish first) blitted into image `index`, scaled to fit it, and the overlay drawn over it where one
    /// is given; submits it and presents the image.
    pub fn blit_and_present(
        &self,
        rec: Recording<'_>,
        frame: &Image,
        index: u32,
        overlay: Option<(&mut OverlayRenderer, &OverlayDraw)>,
        what: &str,
    ) -> Result<Presented> {
        rec.declare(&[], &[ImageUse::new(frame, Access::COPY_READ)]);
        let image = self.images[index as usize];
        let range = COLOR_RANGE;
        // The acquire semaphore's wait covers the transfer stage; the
        // image's old contents are not needed. With an overlay: blit ->
        // drawn over (a colour attachment, loading the blit) -> presented.
        let to_dst = image_barrier(image, range, Access::BLIT_WRITE, Access::BLIT_WRITE, true);
        let to_present = image_barrier(image, range, Access::BLIT_WRITE, Access::PRESENT, false);
        let to_overlay = image_barrier(
            image,
            range,
            Access::BLIT_WRITE,
            Access::COLOR_ATTACHMENT,
            false,
        );
        let overlay_to_present = image_barrier(
            image,
            range,
            Access::COLOR_ATTACHMENT_WRITE,
            Access::PRESENT,
            false,
        );
        let region = [blit_region(frame.extent, self.extent)];
        let blit = vk::BlitImageInfo2::default()
            .src_image(frame.raw)
            .src_image_layout(Access::COPY_READ.layout)
            .dst_image(image)
            .dst_image_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .regions(&region)
            .filter(vk::Filter::LINEAR);
        let device = &self.device.raw;
        // SAFETY: recording; the image belongs to this swapchain and was
        // acquired for this frame.
        unsafe {
            device.cmd_pipeline_barrier2(
                rec.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&[to_dst]),
            )
        };
        // SAFETY: recording; both images are live and in the named layouts
        // (the frame by its declared use, the target just above).
        unsafe { device.cmd_blit_image2(rec.cmd, &blit) };
        let last = match overlay {
            Some((renderer, draw)) => {
                // SAFETY: recording; the image is in the layout the blit left.
                unsafe {
                    device.cmd_pipeline_barrier2(
                        rec.cmd,
                        &vk::DependencyInfo::default().image_memory_barriers(&[to_overlay]),
                    )
                };
                let view = self.views[index as usize].raw();
                renderer.record(rec.cmd, view, self.extent, draw)?;
                overlay_to_present
            }
            None => to_present,
        };
        // SAFETY: recording; the image is in the layout the blit or the
        // overlay left.
        unsafe {
            device.cmd_pipeline_barrier2(
                rec.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&[last]),
            )
        };
        self.submit_and_present(rec, index, what)
    }

    /// Submits `rec`, waiting for the acquire semaphore and signalling the
    /// image's own, and presents image `index` once that is signalled.
    fn submit_and_present(&self, rec: Recording<'_>, index: u32, what: &str) -> Result<Presented> {
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(self.acquired.raw())
            .stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(self.rendered[index as usize].raw())
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        rec.submit_and_wait_with(what, &waits, &signals)?;
        let wait = [self.rendered[index as usize].raw()];
        let swapchains = [self.raw];
        let indices = [index];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its blit submitted, signalling
        // the semaphore this waits on; one thread uses the queue.
        match unsafe { self.loader.queue_present(self.device.queue, &present) } {
            Ok(false) => Ok(Presented::Shown),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Presented::Stale),
            Err(r) => Err(Error::vk("vkQueuePresentKHR", what, r)),
        }
    }
}

/// A swapchain image's one level and layer of colour.
const COLOR_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

/// The whole of an image of `from` pixels onto one of `to`.
fn blit_region(from: vk::Extent2D, to: vk::Extent2D) -> vk::ImageBlit2<'static> {
    let corner = |e: vk::Extent2D| vk::Offset3D {
        x: e.width as i32,
        y: e.height as i32,
        z: 1,
    };
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    vk::ImageBlit2::default()
        .src_subresource(layers)
        .src_offsets([vk::Offset3D::default(), corner(from)])
        .dst_subresource(layers)
        .dst_offsets([vk::Offset3D::default(), corner(to)])
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // Presentation may still read an image: let the queue finish.
        self.device.wait_idle();
        self.views.clear();
        // SAFETY: made from this device; the queue is idle, so no
        // presentation or submission uses its images or its semaphores,
        // and the surface, a field, outlives this body.
        unsafe { self.loader.destroy_swapchain(self.raw, None) };
    }
}

fn semaphore(device: &Arc<Device>, name: &str) -> Result<Owned<vk::Semaphore>> {
    // SAFETY: a valid create info on a live device.
    let raw = unsafe {
        device
            .raw
            .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
    }
    .vk_context("vkCreateSemaphore", name)?;
    Ok(Owned::new(device, raw, name))
}

fn view(
    device: &Arc<Device>,
    image: vk::Image,
    format: vk::Format,
    i: usize,
) -> Result<Owned<vk::ImageView>> {
    let name = format!("swapchain image {i} view");
    let info = vk::ImageViewCreateInfo::default()
        .image(image)
        .view_type(vk::ImageViewType::TYPE_2D)
        .format(format)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        });
    // SAFETY: a valid create info of a live swapchain image on its device.
    let raw = unsafe { device.raw.create_image_view(&info, None) }
        .vk_context("vkCreateImageView", &name)?;
    Ok(Owned::new(device, raw, &name))
}
