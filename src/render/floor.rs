//! The bench's floor (issue 7; not part of the paper's pipeline): the same
//! number of triangles the grass produced, over the same pixels, drawn by a
//! pipeline of a vertex and a fragment shader only (glsl/bench/). Grass
//! draw time over floor time says what the tessellation and geometry
//! stages cost on a device.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::commands::Commands;
use crate::gpu::descriptors::{
    create_pipeline_layout, create_set_layout, BufferSet, LayoutBinding,
};
use crate::gpu::timing::TimestampQueries;
use crate::gpu::{Buffer, Gpu, MemoryLocation};
use crate::reflect::DescriptorKind;
use crate::render::frame::{depth_cleared, full_area, to_attachments};
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::pipelines::{create_pipeline, PipelineDesc, TargetFormats};
use crate::render::targets::RenderTargets;
use crate::shaders::{self, Spirv};

pub const FLOOR_STAGES: &[&Spirv] = &[&shaders::BENCH_FLOOR_VERT, &shaders::BENCH_FLOOR_FRAG];

/// Set 0 of the floor: the frame uniforms and the blades' control points.
pub const FLOOR_SET: &[LayoutBinding] = &[
    LayoutBinding {
        set: 0,
        binding: 0,
        ty: DescriptorKind::UniformBuffer,
        stages: vk::ShaderStageFlags::VERTEX,
    },
    LayoutBinding {
        set: 0,
        binding: 1,
        ty: DescriptorKind::StorageBuffer,
        stages: vk::ShaderStageFlags::VERTEX,
    },
];

/// Push constant: quads per blade.
const PUSH_BYTES: u32 = 4;

/// What the floor draws: `segments` quads along each of `blades` blades.
#[derive(Clone, Copy, Debug)]
pub struct FloorShape {
    pub blades: u32,
    pub segments: u32,
}

pub struct FloorPass {
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    uniforms: Buffer,
    set: BufferSet,
    timestamps: TimestampQueries,
    /// The blades' control points, written by the grass dynamics (compute).
    blade_vertices: vk::Buffer,
}

impl FloorPass {
    /// `None` where the device has no timestamps (the floor is only timed).
    pub fn new(gpu: &Gpu, formats: TargetFormats, blade_vertices: &Buffer) -> Result<Option<Self>> {
        let Some(timestamps) = TimestampQueries::new(gpu, 1, "floor timestamps")? else {
            return Ok(None);
        };
        let mut made = Made::default();
        match Self::build(gpu, formats, blade_vertices, &mut made) {
            Ok((pipeline, uniforms, set)) => Ok(Some(Self {
                set_layout: made.set_layout,
                layout: made.layout,
                pipeline,
                uniforms,
                set,
                timestamps,
                blade_vertices: blade_vertices.raw,
            })),
            Err(e) => {
                made.destroy(gpu);
                timestamps.destroy(gpu);
                Err(e)
            }
        }
    }

    fn build(
        gpu: &Gpu,
        formats: TargetFormats,
        blade_vertices: &Buffer,
        made: &mut Made,
    ) -> Result<(vk::Pipeline, Buffer, BufferSet)> {
        made.set_layout = create_set_layout(gpu, FLOOR_SET, "floor set layout")?;
        made.layout = create_pipeline_layout(
            gpu,
            made.set_layout,
            Some((vk::ShaderStageFlags::VERTEX, PUSH_BYTES)),
            "floor pipeline layout",
        )?;
        let pipeline = create_pipeline(
            gpu,
            made.layout,
            formats,
            &PipelineDesc {
                name: "floor pipeline (vert/frag)",
                stages: FLOOR_STAGES,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: 0,
                depth_test: true,
                shadow: false,
            },
        )?;
        made.pipeline = Some(pipeline);
        let uniforms = Buffer::new(
            gpu,
            "floor uniforms",
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        match BufferSet::new(
            gpu,
            made.set_layout,
            FLOOR_SET,
            &[uniforms.raw, blade_vertices.raw],
            "floor descriptor set",
        ) {
            Ok(set) => {
                made.pipeline = None;
                Ok((pipeline, uniforms, set))
            }
            Err(e) => {
                uniforms.destroy(gpu);
                Err(e)
            }
        }
    }

    /// Draws `shape.blades` x `shape.segments` quads (2 triangles each)
    /// into `targets` once per frame, `frames` times, one submission each,
    /// and returns the GPU ms of each draw.
    pub fn time(
        &mut self,
        gpu: &Gpu,
        commands: &Commands,
        targets: &RenderTargets,
        uniforms: &FrameUniforms,
        shape: FloorShape,
        frames: u32,
    ) -> Result<Vec<f64>> {
        let segments = shape.segments;
        let vertices = (shape.blades as u64) * (segments as u64) * 6;
        let vertices = u32::try_from(vertices).map_err(|_| {
            Error::InvalidInput(format!(
                "the floor's {vertices} vertices do not fit one draw; bench fewer blades"
            ))
        })?;
        self.uniforms.write(0, std::slice::from_ref(uniforms));
        let device = &gpu.device.raw;
        let mut times = Vec::with_capacity(frames as usize);
        for _ in 0..frames {
            let cmd = commands.begin(gpu)?;
            self.timestamps.reset(gpu, cmd);
            // The same transitions as a frame's (the resolve image too,
            // unused here: the next frame transitions it again).
            let barriers = to_attachments(targets);
            let color = [vk::RenderingAttachmentInfo::default()
                .image_view(targets.color.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)];
            let depth = depth_cleared(targets.depth.view, vk::AttachmentStoreOp::DONT_CARE);
            let (area, viewport) = full_area(targets.extent);
            let rendering = vk::RenderingInfo::default()
                .render_area(area)
                .layer_count(1)
                .color_attachments(&color)
                .depth_attachment(&depth);
            // SAFETY: recording into our own command buffer; the targets,
            // pipeline, set and query pool are alive until after the wait.
            // The grass kernel's last writes to the control points, made
            // visible to this vertex shader's storage reads.
            let points = [vk::BufferMemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::VERTEX_SHADER)
                .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ)
                .buffer(self.blade_vertices)
                .offset(0)
                .size(vk::WHOLE_SIZE)];
            unsafe {
                device.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .image_memory_barriers(&barriers)
                        .buffer_memory_barriers(&points),
                );
                device.cmd_begin_rendering(cmd, &rendering);
                device.cmd_set_viewport(cmd, 0, &[viewport]);
                device.cmd_set_scissor(cmd, 0, &[area]);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout,
                    0,
                    &[self.set.set],
                    &[],
                );
                device.cmd_push_constants(
                    cmd,
                    self.layout,
                    vk::ShaderStageFlags::VERTEX,
                    0,
                    &segments.to_ne_bytes(),
                );
            }
            self.timestamps.stamp(gpu, cmd, 0, false);
            unsafe { device.cmd_draw(cmd, vertices, 1, 0, 0) };
            self.timestamps.stamp(gpu, cmd, 0, true);
            unsafe { device.cmd_end_rendering(cmd) };
            commands.submit_and_wait(gpu, "drawing the bench floor")?;
            times.extend(self.timestamps.read_ms(gpu, 1)?);
        }
        Ok(times)
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.wait_idle();
        self.set.destroy(gpu);
        self.uniforms.destroy(gpu);
        self.timestamps.destroy(gpu);
        Made {
            set_layout: self.set_layout,
            layout: self.layout,
            pipeline: Some(self.pipeline),
        }
        .destroy(gpu);
    }
}

/// The floor's layouts and pipeline as far as they were made.
#[derive(Default)]
struct Made {
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: Option<vk::Pipeline>,
}

impl Made {
    fn destroy(self, gpu: &Gpu) {
        let device = &gpu.device.raw;
        // SAFETY: nothing in flight uses these; null handles are ignored.
        unsafe {
            if let Some(p) = self.pipeline {
                device.destroy_pipeline(p, None);
            }
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
