//! The grass dynamics on GPU compute (paper section 4): glsl/grass/step.comp,
//! one invocation per blade, recorded into the frame's command buffer right
//! after the wind step. It samples the wind velocity buffer at each tip and
//! writes the deformed control points into the vertex buffer the blade
//! pipeline draws: the vertex data never goes through the CPU.
//!
//! The pass binds two buffers it does not own (the vertex buffer and the
//! wind velocity); their owners must outlive it.

use ash::vk;

use crate::error::{try_collect, Error, Result};
use crate::gpu::commands::Commands;
use crate::gpu::descriptors::{
    create_pipeline_layout, create_set_layout, BufferSet, LayoutBinding,
};
use crate::gpu::{shader, Buffer, Gpu, MemoryLocation};
use crate::sim::grass::{substeps, GrassBlade, GrassState};
use crate::sim::wind::WindGrid;
use crate::sim::BladeVertex;

const LOCAL_SIZE: u32 = 64;

/// Push constants of glsl/grass/step.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GrassPush {
    pub cells: [u32; 4],
    pub origin: [f32; 4],
    pub cell_size: [f32; 4],
    /// x: blades, y: substeps, z: offset (floats) of the wind copy to sample.
    pub control: [u32; 4],
    /// x: simulation step dt, y: substep h = dt / substeps (s).
    pub step: [f32; 4],
}

/// Set 0 of the grass kernel.
pub const GRASS_SET: &[LayoutBinding] = &[
    LayoutBinding::compute_storage(0), // blades (rest shape and physics)
    LayoutBinding::compute_storage(1), // state (angles, angular velocities)
    LayoutBinding::compute_storage(2), // vertices: the blade pipeline's vertex buffer
    LayoutBinding::compute_storage(3), // wind velocity
];

pub struct GrassPass {
    blades: Buffer,
    states: Buffer,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    set: Option<BufferSet>,
    push: GrassPush,
    blade_count: u32,
}

impl GrassPass {
    /// Uploads the blades and their rest state and builds the kernel.
    /// `vertices` must hold 4 `BladeVertex` per blade; `wind_velocity`
    /// holds velocity copies in the layout of glsl/common/wind_grid.glsl
    /// for `grid`. The simulation step is `dt`; substeps follow from the
    /// stiffest blade (`sim::grass::substeps`).
    pub fn new(
        gpu: &Gpu,
        commands: &Commands,
        blades: &[GrassBlade],
        vertices: &Buffer,
        wind_velocity: &Buffer,
        grid: &WindGrid,
        dt: f32,
    ) -> Result<Self> {
        let blade_count = u32::try_from(blades.len())
            .ok()
            .filter(|&n| n > 0 && n <= u32::MAX / 4)
            .ok_or_else(|| {
                Error::InvalidInput(format!("{} blades cannot be simulated", blades.len()))
            })?;
        let needed = blades.len() as u64 * 4 * std::mem::size_of::<BladeVertex>() as u64;
        if vertices.size < needed {
            return Err(Error::InvalidInput(format!(
                "the vertex buffer holds {} bytes, {needed} needed for {} blades",
                vertices.size,
                blades.len()
            )));
        }
        let substeps = substeps(blades, dt)?;
        let face_count: u64 = (0..3)
            .map(|a| grid.face_dims(a).as_u64vec3().element_product())
            .sum();
        let push = GrassPush {
            cells: [grid.cells.x, grid.cells.y, grid.cells.z, face_count as u32],
            origin: grid.origin.extend(0.0).to_array(),
            cell_size: grid.cell.extend(0.0).to_array(),
            control: [blade_count, substeps, 0, 0],
            step: [dt, dt / substeps as f32, 0.0, 0.0],
        };

        // Host memory first: failing here leaves nothing on the GPU to undo.
        let rest = try_collect(
            blades.len(),
            std::iter::repeat(GrassState::default()),
            "the grass state",
        )?;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let rw = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let blades_buffer = Buffer::with_data(
            gpu,
            commands,
            "grass blades (rest shape, physics)",
            bytemuck::cast_slice(blades),
            usage,
            compute,
            vk::AccessFlags2::SHADER_STORAGE_READ,
        )?;
        let states = match Buffer::with_data(
            gpu,
            commands,
            "grass state (angles, angular velocities)",
            bytemuck::cast_slice(&rest),
            usage,
            compute,
            rw,
        ) {
            Ok(b) => b,
            Err(e) => {
                blades_buffer.destroy(gpu);
                return Err(e);
            }
        };
        let mut pass = Self {
            blades: blades_buffer,
            states,
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            set: None,
            push,
            blade_count,
        };
        match pass.build(gpu, vertices, wind_velocity) {
            Ok(()) => Ok(pass),
            Err(e) => {
                pass.destroy(gpu);
                Err(e)
            }
        }
    }

    fn build(&mut self, gpu: &Gpu, vertices: &Buffer, wind_velocity: &Buffer) -> Result<()> {
        self.set_layout = create_set_layout(gpu, GRASS_SET, "grass set layout")?;
        let push = (
            vk::ShaderStageFlags::COMPUTE,
            std::mem::size_of::<GrassPush>() as u32,
        );
        self.layout =
            create_pipeline_layout(gpu, self.set_layout, Some(push), "grass pipeline layout")?;
        self.pipeline =
            shader::compute_pipeline(gpu, self.layout, &crate::shaders::GRASS_STEP_COMP)?;
        self.set = Some(BufferSet::new(
            gpu,
            self.set_layout,
            GRASS_SET,
            &[
                self.blades.raw,
                self.states.raw,
                vertices.raw,
                wind_velocity.raw,
            ],
            "grass descriptor set",
        )?);
        Ok(())
    }

    pub fn blade_count(&self) -> u32 {
        self.blade_count
    }

    /// Symplectic Euler substeps per simulation step.
    pub fn substeps(&self) -> u32 {
        self.push.control[1]
    }

    /// Records one simulation step into `cmd`, sampling the wind velocity
    /// copy that starts `wind_offset` floats into the wind buffer (0 for
    /// `WindPass`'s state). Waits for earlier compute (the wind step, the
    /// previous grass step) and for the previous draw's vertex reads; ends
    /// with the vertices visible to the vertex input stage and to compute.
    pub fn record_step(&self, gpu: &Gpu, cmd: vk::CommandBuffer, wind_offset: u32) {
        let device = &gpu.device.raw;
        let mut push = self.push;
        push.control[2] = wind_offset;
        let before = [vk::MemoryBarrier2::default()
            .src_stage_mask(
                vk::PipelineStageFlags2::COMPUTE_SHADER
                    | vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                    | vk::PipelineStageFlags2::COPY,
            )
            .src_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE,
            )
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        let after = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(
                vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                    | vk::PipelineStageFlags2::COMPUTE_SHADER,
            )
            .dst_access_mask(
                vk::AccessFlags2::VERTEX_ATTRIBUTE_READ
                    | vk::AccessFlags2::SHADER_STORAGE_READ
                    | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        let set = self.set.as_ref().expect("built").set;
        // SAFETY: recording into a live command buffer; pipeline, layout,
        // set and every buffer the set names are alive (see module doc).
        unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&before),
            );
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(&push),
            );
            device.cmd_dispatch(cmd, self.blade_count.div_ceil(LOCAL_SIZE), 1, 1);
            device
                .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&after));
        }
    }

    /// Every blade's angles and angular velocities (for tests and reports).
    pub fn read_states(&self, gpu: &Gpu, commands: &Commands) -> Result<Vec<GrassState>> {
        self.states
            .read_back(gpu, commands, self.blade_count as usize)
    }

    pub fn destroy(self, gpu: &Gpu) {
        if let Some(set) = self.set {
            set.destroy(gpu);
        }
        // SAFETY: the owner waited for the GPU; null handles are no-ops.
        unsafe {
            let device = &gpu.device.raw;
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
        self.states.destroy(gpu);
        self.blades.destroy(gpu);
    }
}

/// A device buffer for `blades` blades' vertices that the grass kernel can
/// write and the tests can read: what `Renderer` makes for drawing.
/// Device memory the grass of `blades` blades needs: the vertex buffer the
/// pipeline draws, the rest shapes with physics, and the state.
pub fn device_bytes(blades: usize) -> u64 {
    use std::mem::size_of;
    let per_blade =
        4 * size_of::<BladeVertex>() + size_of::<GrassBlade>() + size_of::<GrassState>();
    blades as u64 * per_blade as u64
}

pub fn vertex_buffer(gpu: &Gpu, name: &str, blades: usize) -> Result<Buffer> {
    Buffer::new(
        gpu,
        name,
        (blades * 4 * std::mem::size_of::<BladeVertex>()) as u64,
        vk::BufferUsageFlags::VERTEX_BUFFER
            | vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
    )
}
