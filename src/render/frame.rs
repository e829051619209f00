//! Frame orchestration: records one frame (sky, ground, grass through the
//! tessellation and geometry stages), resolves the MSAA image, and reads it
//! back to the host.

use ash::vk;

use crate::error::{try_collect, Error, Result};
use crate::gpu::commands::Commands;
use crate::gpu::descriptors::{Bound, BufferSet};
use crate::gpu::timing::{FrameTimings, Phase, PhaseTimer, PipelineStatistics, StatisticsQuery};
use crate::gpu::{Buffer, Gpu, Image, MemoryLocation};
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::pipelines::{RenderPipelines, FRAME_SET};
use crate::render::shadow::ShadowMap;
use crate::render::targets::{choose_samples, RenderTargets};
use crate::render::textures::SurfaceTextures;
use crate::sim::{Blade, BladeVertex};

/// A finished frame on the host.
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, sRGB-encoded, rows top to bottom.
    pub rgba: Vec<u8>,
    /// Counters of the grass draw alone (None where unsupported).
    pub statistics: Option<PipelineStatistics>,
    /// GPU time of each phase (None where the device has no timestamps).
    pub timings: Option<FrameTimings>,
}

/// Everything one offscreen view of the grass needs on the GPU.
pub struct Renderer {
    pub targets: RenderTargets,
    pipelines: RenderPipelines,
    shadow: ShadowMap,
    textures: SurfaceTextures,
    frame_set: BufferSet,
    uniforms: Buffer,
    /// The blades' control points: the vertex buffer of the blade pipeline.
    pub blade_vertices: Buffer,
    blade_count: u32,
    statistics: StatisticsQuery,
    timer: Option<PhaseTimer>,
    commands: Commands,
}

/// Pieces made so far while building a Renderer, destroyed on failure.
#[derive(Default)]
struct Partial {
    targets: Option<RenderTargets>,
    pipelines: Option<RenderPipelines>,
    shadow: Option<ShadowMap>,
    textures: Option<SurfaceTextures>,
    frame_set: Option<BufferSet>,
    uniforms: Option<Buffer>,
    blade_vertices: Option<Buffer>,
    statistics: Option<StatisticsQuery>,
    timer: Option<PhaseTimer>,
    commands: Option<Commands>,
}

impl Partial {
    fn destroy(self, gpu: &Gpu) {
        if let Some(x) = self.commands {
            x.destroy(gpu);
        }
        if let Some(x) = self.statistics {
            x.destroy(gpu);
        }
        if let Some(x) = self.timer {
            x.destroy(gpu);
        }
        if let Some(x) = self.blade_vertices {
            x.destroy(gpu);
        }
        if let Some(x) = self.uniforms {
            x.destroy(gpu);
        }
        if let Some(x) = self.frame_set {
            x.destroy(gpu);
        }
        if let Some(x) = self.textures {
            x.destroy(gpu);
        }
        if let Some(x) = self.shadow {
            x.destroy(gpu);
        }
        if let Some(x) = self.pipelines {
            x.destroy(gpu);
        }
        if let Some(x) = self.targets {
            x.destroy(gpu);
        }
    }
}

impl Renderer {
    /// Builds the targets and pipelines for a `width` x `height` image with
    /// up to `msaa` samples and a `shadow_map` x `shadow_map` shadow map (0:
    /// no shadows), and uploads the blades' rest shape.
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        msaa: u32,
        shadow_map: u32,
        blades: &[Blade],
    ) -> Result<Self> {
        let mut partial = Partial::default();
        match Self::build(gpu, width, height, msaa, shadow_map, blades, &mut partial) {
            Ok(r) => Ok(r),
            Err(e) => {
                partial.destroy(gpu);
                Err(e)
            }
        }
    }

    fn build(
        gpu: &Gpu,
        width: u32,
        height: u32,
        msaa: u32,
        shadow_map: u32,
        blades: &[Blade],
        p: &mut Partial,
    ) -> Result<Self> {
        let blade_count = u32::try_from(blades.len())
            .ok()
            .filter(|&n| n > 0 && (n as u64) * 4 <= u32::MAX as u64)
            .ok_or_else(|| {
                Error::InvalidInput(format!(
                    "{} blades cannot be drawn in one call",
                    blades.len()
                ))
            })?;

        let samples = choose_samples(gpu, msaa);
        let targets = p
            .targets
            .insert(RenderTargets::new(gpu, width, height, samples)?);
        let formats = targets.formats();
        let pipelines = p
            .pipelines
            .insert(RenderPipelines::new(gpu, formats, shadow_map > 0)?);
        let max_side = gpu.device.limits().max_image_dimension2_d;
        if shadow_map > max_side {
            return Err(Error::InvalidInput(format!(
                "--shadow-map {shadow_map} is larger than this device's largest image ({max_side}); use 0..={max_side}"
            )));
        }
        let shadow = p.shadow.insert(ShadowMap::new(
            gpu,
            shadow_map,
            pipelines.shadow_set_layout,
        )?);

        let uniforms = p.uniforms.insert(Buffer::new(
            gpu,
            "frame uniforms",
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?);
        let commands = p.commands.insert(Commands::new(gpu, "frame commands")?);
        let textures = p.textures.insert(SurfaceTextures::new(gpu, commands)?);
        let [map_binding, sampler_binding] = shadow.bindings();
        let [grass_binding, ground_binding, surface_sampler] = textures.bindings();
        p.frame_set = Some(BufferSet::with(
            gpu,
            pipelines.set_layout,
            FRAME_SET,
            &[
                Bound::Buffer(uniforms.raw),
                map_binding,
                sampler_binding,
                grass_binding,
                ground_binding,
                surface_sampler,
            ],
            "frame descriptor set",
        )?);

        let vertices: Vec<BladeVertex> = try_collect(
            4 * blades.len(),
            blades.iter().flat_map(Blade::vertices),
            "the blades' control points",
        )?;
        p.statistics = Some(StatisticsQuery::new(gpu)?);
        p.timer = PhaseTimer::new(gpu, 16)?;
        // The grass dynamics (compute) writes this buffer in place each
        // step; the draw reads it as its vertex buffer. Device-local; the
        // rest shape is uploaded once here.
        p.blade_vertices = Some(Buffer::with_data(
            gpu,
            commands,
            "blade control points (vertex buffer)",
            bytemuck::cast_slice(&vertices),
            vk::BufferUsageFlags::VERTEX_BUFFER
                | vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC,
            vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT,
            vk::AccessFlags2::VERTEX_ATTRIBUTE_READ,
        )?);

        let p = std::mem::take(p);
        Ok(Self {
            targets: p.targets.unwrap(),
            pipelines: p.pipelines.unwrap(),
            shadow: p.shadow.unwrap(),
            textures: p.textures.unwrap(),
            frame_set: p.frame_set.unwrap(),
            uniforms: p.uniforms.unwrap(),
            blade_vertices: p.blade_vertices.unwrap(),
            blade_count,
            statistics: p.statistics.unwrap(),
            timer: p.timer,
            commands: p.commands.unwrap(),
        })
    }

    /// The MSAA sample count actually used.
    pub fn samples(&self) -> u32 {
        self.targets.color.samples.as_raw()
    }

    /// Renders one frame and reads it back.
    pub fn render(&mut self, gpu: &Gpu, uniforms: &FrameUniforms) -> Result<Frame> {
        self.render_after(gpu, uniforms, 0, |_, _| {})
    }

    /// Records `simulate` (`steps` wind and grass steps, which end with the
    /// blade vertices visible to the vertex input stage; it is handed the
    /// phase timer to time them) and then the frame into one command
    /// buffer, submits it and reads the frame back.
    pub fn render_after(
        &mut self,
        gpu: &Gpu,
        uniforms: &FrameUniforms,
        steps: u64,
        simulate: impl FnOnce(vk::CommandBuffer, Option<&mut PhaseTimer>),
    ) -> Result<Frame> {
        let mut uniforms = *uniforms;
        uniforms.shadow = self.shadow.params();
        self.uniforms.write(0, std::slice::from_ref(&uniforms));
        self.shadow.write_uniforms(&uniforms);
        // Two pairs per simulation step, five for the frame's own phases.
        if let Some(timer) = self.timer.as_mut() {
            let pairs = u32::try_from(steps.saturating_mul(2).saturating_add(5)).map_err(|_| {
                Error::InvalidInput(format!(
                    "{steps} simulation steps in one frame are too many to time"
                ))
            })?;
            timer.reserve(gpu, pairs)?;
        }
        let cmd = self.commands.begin(gpu)?;
        let mut timer = self.timer.take();
        let frame_span = timer.as_mut().map(|t| {
            t.reset(gpu, cmd);
            t.begin(gpu, cmd, Phase::Frame)
        });
        simulate(cmd, timer.as_mut());
        let span = timer.as_mut().map(|t| t.begin(gpu, cmd, Phase::Shadow));
        self.shadow.record(
            gpu,
            cmd,
            self.pipelines.shadow,
            self.pipelines.shadow_layout,
            self.blade_vertices.raw,
            self.blade_count,
        );
        if let (Some(t), Some(span)) = (&timer, span) {
            t.end(gpu, cmd, span);
        }
        self.record(gpu, cmd, timer.as_mut());
        if let (Some(t), Some(span)) = (&timer, frame_span) {
            t.end(gpu, cmd, span);
        }
        self.timer = timer;
        self.commands.submit_and_wait(gpu, "rendering a frame")?;
        let statistics = self.statistics.read(gpu)?;
        let timings = match &self.timer {
            Some(t) => Some(t.read(gpu)?),
            None => None,
        };
        let extent = self.targets.extent;
        let rgba = self
            .targets
            .readback
            .mapped()
            .expect("readback buffer is host-visible")
            .to_vec();
        Ok(Frame {
            width: extent.width,
            height: extent.height,
            rgba,
            statistics,
            timings,
        })
    }

    fn record(&self, gpu: &Gpu, cmd: vk::CommandBuffer, mut timer: Option<&mut PhaseTimer>) {
        let device = &gpu.device.raw;
        let t = &self.targets;
        let extent = t.extent;
        self.statistics.reset(gpu, cmd);
        let colour_span = timer
            .as_deref_mut()
            .map(|t| t.begin(gpu, cmd, Phase::Colour));

        let to_attachment = to_attachments(t);
        // SAFETY (this and the commands below): recording into our own
        // command buffer; every handle is owned by this Renderer and alive.
        unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
            );
        }

        let mut color_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(t.color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.0, 0.0, 0.0, 1.0],
                },
            });
        if let Some(resolve) = &t.resolve {
            color_attachment = color_attachment
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(resolve.view)
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        }
        let color_attachments = [color_attachment];
        let depth_attachment = depth_cleared(t.depth.view, vk::AttachmentStoreOp::DONT_CARE);
        let (area, viewport) = full_area(extent);
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachments)
            .depth_attachment(&depth_attachment);
        let p = &self.pipelines;
        unsafe {
            device.cmd_begin_rendering(cmd, &rendering);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                p.layout,
                0,
                &[self.frame_set.set],
                &[],
            );

            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.sky);
            device.cmd_draw(cmd, 3, 1, 0, 0);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.ground);
            device.cmd_draw(cmd, 6, 1, 0, 0);

            // The grass: one 4-point patch per blade, counted by the query.
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.blade);
            device.cmd_bind_vertex_buffers(cmd, 0, &[self.blade_vertices.raw], &[0]);
        }
        let draw_span = timer
            .as_deref_mut()
            .map(|t| t.begin(gpu, cmd, Phase::GrassDraw));
        unsafe {
            self.statistics.begin(gpu, cmd);
            device.cmd_draw(cmd, self.blade_count * 4, 1, 0, 0);
            self.statistics.end(gpu, cmd);
        }
        if let (Some(t), Some(span)) = (timer.as_deref(), draw_span) {
            t.end(gpu, cmd, span);
        }
        unsafe { device.cmd_end_rendering(cmd) };
        if let (Some(t), Some(span)) = (timer.as_deref(), colour_span) {
            t.end(gpu, cmd, span);
        }
        let readback_span = timer
            .as_deref_mut()
            .map(|t| t.begin(gpu, cmd, Phase::Readback));

        // Final image -> copy source; then copy into the host buffer.
        let final_image = t.final_image();
        let to_copy = [image_barrier(
            final_image,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        )];
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            },
        };
        let to_host = [vk::BufferMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)
            .buffer(t.readback.raw)
            .offset(0)
            .size(vk::WHOLE_SIZE)];
        unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_copy),
            );
            device.cmd_copy_image_to_buffer(
                cmd,
                final_image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                t.readback.raw,
                &[region],
            );
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().buffer_memory_barriers(&to_host),
            );
        }
        if let (Some(t), Some(span)) = (timer.as_deref(), readback_span) {
            t.end(gpu, cmd, span);
        }
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.wait_idle();
        Partial {
            targets: Some(self.targets),
            pipelines: Some(self.pipelines),
            shadow: Some(self.shadow),
            textures: Some(self.textures),
            frame_set: Some(self.frame_set),
            uniforms: Some(self.uniforms),
            blade_vertices: Some(self.blade_vertices),
            statistics: Some(self.statistics),
            timer: self.timer,
            commands: Some(self.commands),
        }
        .destroy(gpu);
    }
}

/// Layout transitions of `t`'s images into attachment layouts, contents
/// discarded. The previous frame (or the bench's floor) wrote these images
/// and copied from the final one, so wait for those writes and reads first.
pub(crate) fn to_attachments(t: &RenderTargets) -> Vec<vk::ImageMemoryBarrier2<'static>> {
    let mut to_attachment = vec![
        image_barrier(
            &t.color,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        ),
        image_barrier(
            &t.depth,
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        ),
    ];
    if t.resolve.is_none() {
        // At 1x the colour target is also the copy source of the last frame.
        to_attachment[0].src_stage_mask |= vk::PipelineStageFlags2::COPY;
    }
    if let Some(resolve) = &t.resolve {
        to_attachment.push(image_barrier(
            resolve,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        ));
    }
    to_attachment
}

/// A depth attachment cleared to the far plane (1.0) on load.
pub(crate) fn depth_cleared(
    view: vk::ImageView,
    store: vk::AttachmentStoreOp,
) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(store)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        })
}

/// The render area and viewport covering all of `extent`, depth 0..1.
pub(crate) fn full_area(extent: vk::Extent2D) -> (vk::Rect2D, vk::Viewport) {
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent,
    };
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    (area, viewport)
}

pub(crate) fn image_barrier(
    image: &Image,
    src_stage: vk::PipelineStageFlags2,
    src_access: vk::AccessFlags2,
    dst_stage: vk::PipelineStageFlags2,
    dst_access: vk::AccessFlags2,
    old: vk::ImageLayout,
    new: vk::ImageLayout,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)
        .old_layout(old)
        .new_layout(new)
        .image(image.raw)
        .subresource_range(image.subresource_range())
}
