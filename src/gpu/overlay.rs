//! The Vulkan side of the viewer's overlay: egui's triangles drawn into a
//! swapchain image after the frame's blit, by egui-ash-renderer (dynamic
//! rendering, its own small allocator). egui's font atlas is uploaded
//! through a command pool of this module's own, between frames.
//!
//! The renderer's own objects (its pipeline, descriptor pool, vertex
//! buffers, textures) are made and destroyed by the crate, unnamed; they
//! go in `Drop` before the device, which the validation layer's object
//! tracker checks at teardown.

use std::sync::Arc;

use ash::vk;
use egui_ash_renderer::{DynamicRendering, Options, RenderMode, Renderer, RendererError};

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::depends_on::DependsOn;
use crate::gpu::device::Device;
use crate::gpu::owned::Owned;
use crate::gpu::Gpu;

/// What one frame's overlay draws: egui's tessellated shapes and the
/// points-to-pixels scale they were laid out at.
pub struct OverlayDraw {
    pub primitives: Vec<egui::ClippedPrimitive>,
    pub pixels_per_point: f32,
}

pub struct OverlayRenderer {
    /// The renderer, which uploads egui's textures with the pool it keeps
    /// alive (and, through the pool, the device).
    renderer:
        DependsOn<Renderer<egui_ash_renderer::allocator::DefaultAllocator>, Owned<vk::CommandPool>>,
    device: Arc<Device>,
    /// The colour format the renderer's pipeline was made for.
    pub format: vk::Format,
}

fn overlay_error(call: &'static str, e: RendererError) -> Error {
    match e {
        RendererError::Vulkan(r) => Error::vk(call, "the viewer's overlay", r),
        other => Error::InvalidInput(format!("the viewer's overlay failed in {call}: {other}")),
    }
}

impl OverlayRenderer {
    /// A renderer drawing into images of `format` (a swapchain's).
    pub fn new(gpu: &Gpu, format: vk::Format) -> Result<Self> {
        let device = gpu.device().clone();
        let pool_info =
            vk::CommandPoolCreateInfo::default().queue_family_index(device.queue_family);
        // SAFETY: a valid create info on a live device.
        let pool = unsafe { device.raw.create_command_pool(&pool_info, None) }
            .vk_context("vkCreateCommandPool", "overlay uploads")?;
        let uploads = Owned::new(&device, pool, "overlay texture uploads pool");
        let srgb = matches!(
            format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        );
        let renderer = Renderer::with_default_allocator(
            &device.instance.raw,
            device.adapter.raw,
            device.raw.clone(),
            RenderMode::DynamicRendering(DynamicRendering {
                color_attachment_format: format,
                depth_attachment_format: None,
                stencil_attachment_format: None,
            }),
            Options {
                // Each frame is waited for before the next is recorded.
                in_flight_frames: 1,
                enable_depth_test: false,
                enable_depth_write: false,
                srgb_framebuffer: srgb,
            },
        )
        .map_err(|e| overlay_error("egui_ash_renderer::Renderer::new", e))?;
        Ok(Self {
            renderer: DependsOn::new(renderer, uploads),
            device,
            format,
        })
    }

    /// Uploads egui's new and changed textures (its font atlas), in
    /// order. Runs its own submissions and waits for them: call between
    /// frames.
    pub fn set_textures(
        &mut self,
        set: &[(egui::TextureId, egui::epaint::ImageDelta)],
    ) -> Result<()> {
        let uploads = self.renderer.keeper().raw();
        for (id, image) in set {
            self.renderer
                .set_texture(self.device.queue, uploads, *id, image)
                .map_err(|e| overlay_error("egui_ash_renderer::Renderer::set_texture", e))?;
        }
        Ok(())
    }

    /// Frees the textures egui no longer uses: after the frame that last
    /// drew with them has completed.
    pub fn free_textures(&mut self, ids: &[egui::TextureId]) -> Result<()> {
        for id in ids {
            self.renderer
                .free_texture(*id)
                .map_err(|e| overlay_error("egui_ash_renderer::Renderer::free_texture", e))?;
        }
        Ok(())
    }

    /// Records `draw` into `view` (an image of `extent` in the colour
    /// attachment layout), over what is there.
    pub(super) fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        view: vk::ImageView,
        extent: vk::Extent2D,
        draw: &OverlayDraw,
    ) -> Result<()> {
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        };
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color);
        // SAFETY: recording, outside rendering; the view is live and in the
        // attachment layout (the caller's barrier put it there).
        unsafe { self.device.raw.cmd_begin_rendering(cmd, &rendering) };
        let drawn = self
            .renderer
            .cmd_draw(cmd, extent, draw.pixels_per_point, &draw.primitives)
            .map_err(|e| overlay_error("egui_ash_renderer::Renderer::cmd_draw", e));
        // SAFETY: recording, inside the rendering begun above.
        unsafe { self.device.raw.cmd_end_rendering(cmd) };
        drawn
    }
}
