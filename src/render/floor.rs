//! The bench's floor (not part of the paper's pipeline): the same
//! number of triangles the grass produced, over the same pixels, drawn by a
//! pipeline of a vertex and a fragment shader only (glsl/bench/). Grass
//! draw time over floor time says what the tessellation and geometry
//! stages cost on a device.

use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::query::TimestampQueries;
use crate::gpu::{
    Access, Attachments, Bound, Buffer, BufferUse, CommandPool, DescriptorKind, DescriptorSet, Gpu,
    GraphicsDesc, LayoutBinding, Pipeline, PipelineLayout, TargetFormats,
};
use crate::interface::FloorPush;
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::renderer::attachments;
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

/// What the floor draws: `segments` quads along each of `blades` blades.
#[derive(Clone, Copy, Debug)]
pub struct FloorShape {
    pub blades: u32,
    pub segments: u32,
}

impl FloorShape {
    /// The grass's segments per blade that `triangles` triangles over
    /// `blades` blades make: each segment 2, the tip's 1 (blade.geom).
    pub fn segments_of(triangles: u64, blades: u64) -> u32 {
        (((triangles + blades) as f64 / (2.0 * blades.max(1) as f64)).round() as u32).max(1)
    }

    /// Its triangles: 2 a segment, 1 at each tip, as the grass's.
    pub fn triangles(&self) -> u64 {
        self.blades as u64 * (2 * self.segments as u64 - 1)
    }
}

pub struct FloorPass {
    set: DescriptorSet,
    uniforms: Buffer,
    pipeline: Pipeline,
    timestamps: TimestampQueries,
}

impl FloorPass {
    /// Draws from `blade_vertices` (the blades' control points, written by
    /// the grass dynamics). `None` where the device has no timestamps (the
    /// floor is only timed).
    pub fn new(gpu: &Gpu, formats: TargetFormats, blade_vertices: &Buffer) -> Result<Option<Self>> {
        let Some(timestamps) = TimestampQueries::new(gpu, 1, "floor timestamps")? else {
            return Ok(None);
        };
        let layout: Arc<PipelineLayout> = PipelineLayout::new::<FloorPush>(
            gpu,
            FLOOR_SET,
            vk::ShaderStageFlags::VERTEX,
            "floor",
        )?;
        let pipeline = Pipeline::graphics(
            gpu,
            &layout,
            &GraphicsDesc {
                name: "floor pipeline (vert/frag)",
                stages: FLOOR_STAGES,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: 0,
                depth_test: true,
                depth_bias: None,
                cull: vk::CullModeFlags::NONE,
                targets: formats,
            },
        )?;
        let uniforms = FrameUniforms::buffer(gpu, "floor uniforms")?;
        let set = DescriptorSet::new(
            gpu,
            &layout,
            FLOOR_SET,
            &[Bound::Buffer(&uniforms), Bound::Buffer(blade_vertices)],
            "floor descriptor set",
        )?;
        Ok(Some(Self {
            set,
            uniforms,
            pipeline,
            timestamps,
        }))
    }

    /// Draws `shape.blades` x `shape.segments` quads (2 triangles each,
    /// the tip's 1: `FloorShape::triangles`)
    /// into `targets` once per frame, `frames` times, one submission each,
    /// and returns the GPU ms of each draw. `blade_vertices` is the buffer
    /// the pass was made with.
    pub fn time(
        &mut self,
        commands: &CommandPool,
        targets: &RenderTargets,
        blade_vertices: &Buffer,
        uniforms: &FrameUniforms,
        shape: FloorShape,
        frames: u32,
    ) -> Result<Vec<f64>> {
        let segments = shape.segments;
        let vertices = 3 * shape.triangles();
        let vertices = u32::try_from(vertices).map_err(|_| {
            Error::InvalidInput(format!(
                "the floor's {vertices} vertices do not fit one draw; bench fewer blades"
            ))
        })?;
        self.uniforms.write(0, std::slice::from_ref(uniforms));
        let mut times = Vec::with_capacity(frames as usize);
        for _ in 0..frames {
            let rec = commands.begin()?;
            self.timestamps.reset(&rec);
            // The same attachments as a frame's (the resolve image too,
            // unused here), and this vertex shader's storage reads of the
            // control points.
            rec.declare(
                &[BufferUse::new(blade_vertices, Access::VERTEX_SHADER_READ)],
                &attachments(targets),
            );
            rec.begin_rendering(&Attachments {
                color: Some((&targets.color, None)),
                depth: &targets.depth,
                store_depth: false,
            });
            rec.bind_pipeline(&self.pipeline);
            rec.bind_set(&self.pipeline, &self.set);
            rec.push_constants(&self.pipeline, &FloorPush { segments });
            self.timestamps.stamp(&rec, 0, false);
            rec.draw(vertices);
            self.timestamps.stamp(&rec, 0, true);
            rec.end_rendering();
            rec.submit_and_wait("drawing the bench floor")?;
            times.extend(self.timestamps.read_ms(1)?);
        }
        Ok(times)
    }
}
