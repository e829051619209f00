//! The wind solver on GPU compute (paper section 3.2): five kernels in
//! glsl/wind/, recorded into the frame's command buffer with a barrier
//! between each. All buffers are made once; a step allocates and uploads
//! nothing (the time and Jacobi parity travel as push constants).
//!
//! Obstacle voxelisation and the classification of every face (free, wall,
//! inflow) happen once on the CPU through `sim::wind::WindField`, the same
//! code the CPU reference steps with, and are uploaded.

use ash::vk;
use bytemuck::Zeroable;

use crate::error::{Error, Result};
use crate::gpu::commands::Commands;
use crate::gpu::descriptors::{
    create_pipeline_layout, create_set_layout, BufferSet, LayoutBinding,
};
use crate::gpu::{shader, Buffer, Gpu, MemoryLocation};
use crate::shaders::{self, Spirv};
use crate::sim::wind::{FaceKind, WindField, WindGrid, WindSettings, WindSource};

/// Waypoints a source's path may have on the GPU.
pub use crate::sim::wind::MAX_PATH_POINTS;
const LOCAL_SIZE: u32 = 64;

/// Push constants of every wind kernel (`Push` in glsl/wind/wind_kernel.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WindPush {
    pub cells: [u32; 4],
    pub origin: [f32; 4],
    pub cell_size: [f32; 4],
    pub step: [f32; 4],
    pub control: [u32; 4],
    pub inflow: [f32; 4],
    pub inflow_phases: [f32; 4],
}

/// One wind source as the kernels read it (`WindSource` in wind_kernel.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuWindSource {
    pub position_radius: [f32; 4],
    pub direction_strength: [f32; 4],
    pub motion: [f32; 4],
    pub gust: [f32; 4],
    pub gust_phases: [f32; 4],
    pub path: [[f32; 4]; MAX_PATH_POINTS],
}

impl GpuWindSource {
    pub fn from_source(s: &WindSource) -> Result<Self> {
        if s.path.len() > MAX_PATH_POINTS {
            return Err(Error::InvalidInput(format!(
                "a wind source path has {} points, use at most {MAX_PATH_POINTS}",
                s.path.len()
            )));
        }
        let mut path = [[0.0; 4]; MAX_PATH_POINTS];
        for (dst, p) in path.iter_mut().zip(&s.path) {
            *dst = p.extend(0.0).to_array();
        }
        let dir = s.direction.try_normalize().unwrap_or(glam::Vec3::X);
        let p = s.gust.phases();
        Ok(Self {
            position_radius: s.position.extend(s.radius).to_array(),
            direction_strength: dir.extend(s.strength).to_array(),
            motion: [
                s.rotation_speed,
                s.path_speed,
                s.path.len() as f32,
                s.off_after.unwrap_or(f32::INFINITY),
            ],
            gust: [s.gust.amplitude, s.gust.frequency, 0.0, 0.0],
            gust_phases: [p[0], p[1], p[2], 0.0],
            path,
        })
    }
}

/// Set 0 of the wind kernels.
pub const WIND_SET: &[LayoutBinding] = &[
    LayoutBinding::compute_storage(0), // velocity (two copies)
    LayoutBinding::compute_storage(1), // face kinds
    LayoutBinding::compute_storage(2), // solid cells
    LayoutBinding::compute_storage(3), // pressure (two copies)
    LayoutBinding::compute_storage(4), // divergence
    LayoutBinding::compute_storage(5), // sources
];

/// The kernels in the order a step runs them.
pub const WIND_KERNELS: [&Spirv; 5] = [
    &shaders::WIND_FORCES_COMP,
    &shaders::WIND_ADVECT_COMP,
    &shaders::WIND_DIVERGENCE_COMP,
    &shaders::WIND_JACOBI_COMP,
    &shaders::WIND_PROJECT_COMP,
];
const FORCES: usize = 0;
const ADVECT: usize = 1;
const DIVERGENCE: usize = 2;
const JACOBI: usize = 3;
const PROJECT: usize = 4;

/// The solver's buffers, made once.
struct WindBuffers {
    /// Velocity, two copies of every face: A (state) then B (advected).
    velocity: Buffer,
    faces: Buffer,
    solid: Buffer,
    pressure: Buffer,
    divergence: Buffer,
    sources: Buffer,
}

impl WindBuffers {
    fn new(
        gpu: &Gpu,
        commands: &Commands,
        field: &WindField,
        gpu_sources: &[GpuWindSource],
        face_count: u32,
        cell_count: u32,
    ) -> Result<Self> {
        let mut made: Vec<Buffer> = Vec::with_capacity(6);
        match Self::fill(
            gpu,
            commands,
            field,
            gpu_sources,
            face_count,
            cell_count,
            &mut made,
        ) {
            Ok(()) => {
                let [velocity, faces, solid, pressure, divergence, sources]: [Buffer; 6] = made
                    .try_into()
                    .unwrap_or_else(|_| unreachable!("fill makes six buffers"));
                Ok(Self {
                    velocity,
                    faces,
                    solid,
                    pressure,
                    divergence,
                    sources,
                })
            }
            Err(e) => {
                for b in made {
                    b.destroy(gpu);
                }
                Err(e)
            }
        }
    }

    /// Pushes the buffers in binding order (`WIND_SET`), each as soon as it exists.
    fn fill(
        gpu: &Gpu,
        commands: &Commands,
        field: &WindField,
        gpu_sources: &[GpuWindSource],
        face_count: u32,
        cell_count: u32,
        made: &mut Vec<Buffer>,
    ) -> Result<()> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let rw = storage | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let read = vk::AccessFlags2::SHADER_STORAGE_READ;
        let device_buffer = |name: &str, floats: u64| {
            Buffer::new(gpu, name, 4 * floats, rw, MemoryLocation::GpuOnly)
        };
        let uploaded = |name: &str, bytes: &[u8]| {
            Buffer::with_data(gpu, commands, name, bytes, storage, compute, read)
        };

        made.push(device_buffer(
            "wind velocity (A, B)",
            2 * face_count as u64,
        )?);
        let kinds = field.faces.iter().flatten().map(|k| match k {
            FaceKind::Free => 0,
            FaceKind::Wall => 1,
            FaceKind::Inflow => 2,
        });
        made.push(uploaded("wind face kinds", &u32_bytes(kinds))?);
        made.push(uploaded(
            "wind solid cells",
            &u32_bytes(field.solid.iter().map(|&s| s as u32)),
        )?);
        made.push(device_buffer(
            "wind pressure (ping, pong)",
            2 * cell_count as u64,
        )?);
        made.push(device_buffer("wind divergence", cell_count as u64)?);
        // At least one entry so the binding is never empty.
        let sources: &[GpuWindSource] = if gpu_sources.is_empty() {
            &[GpuWindSource::zeroed()]
        } else {
            gpu_sources
        };
        made.push(uploaded("wind sources", bytemuck::cast_slice(sources))?);

        // The air starts at rest, and the first Jacobi solve starts from
        // zero pressure (later ones from the previous step's).
        let cmd = commands.begin(gpu)?;
        let zeroed = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(compute)
            .dst_access_mask(read | vk::AccessFlags2::SHADER_STORAGE_WRITE)];
        // SAFETY: recording into our command buffer; the buffers are live.
        unsafe {
            let device = &gpu.device.raw;
            device.cmd_fill_buffer(cmd, made[0].raw, 0, vk::WHOLE_SIZE, 0);
            device.cmd_fill_buffer(cmd, made[3].raw, 0, vk::WHOLE_SIZE, 0);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&zeroed),
            );
        }
        commands.submit_and_wait(gpu, "clearing the wind")
    }

    /// In the order of `WIND_SET`.
    fn raw(&self) -> [vk::Buffer; 6] {
        [
            self.velocity.raw,
            self.faces.raw,
            self.solid.raw,
            self.pressure.raw,
            self.divergence.raw,
            self.sources.raw,
        ]
    }

    fn destroy(self, gpu: &Gpu) {
        for b in [
            self.velocity,
            self.faces,
            self.solid,
            self.pressure,
            self.divergence,
            self.sources,
        ] {
            b.destroy(gpu);
        }
    }
}

/// The five kernels' pipelines and their shared layouts.
struct WindKernels {
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipelines: Vec<vk::Pipeline>,
}

impl WindKernels {
    fn new(gpu: &Gpu) -> Result<Self> {
        let mut k = Self {
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipelines: Vec::new(),
        };
        let built = (|| {
            k.set_layout = create_set_layout(gpu, WIND_SET, "wind set layout")?;
            let push = (
                vk::ShaderStageFlags::COMPUTE,
                std::mem::size_of::<WindPush>() as u32,
            );
            k.layout =
                create_pipeline_layout(gpu, k.set_layout, Some(push), "wind pipeline layout")?;
            for spirv in WIND_KERNELS {
                k.pipelines
                    .push(shader::compute_pipeline(gpu, k.layout, spirv)?);
            }
            Ok(())
        })();
        match built {
            Ok(()) => Ok(k),
            Err(e) => {
                k.destroy(gpu);
                Err(e)
            }
        }
    }

    fn destroy(self, gpu: &Gpu) {
        let device = &gpu.device.raw;
        // SAFETY: the owner waited for the GPU; destroying a null handle is a no-op.
        unsafe {
            for p in self.pipelines {
                device.destroy_pipeline(p, None);
            }
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

pub struct WindPass {
    pub grid: WindGrid,
    settings: WindSettings,
    buffers: WindBuffers,
    kernels: WindKernels,
    set: BufferSet,
    face_count: u32,
    cell_count: u32,
}

fn u32_bytes(values: impl Iterator<Item = u32>) -> Vec<u8> {
    values.flat_map(u32::to_le_bytes).collect()
}

impl WindPass {
    pub fn new(
        gpu: &Gpu,
        commands: &Commands,
        grid: WindGrid,
        settings: &WindSettings,
    ) -> Result<Self> {
        let face_count: u64 = (0..3)
            .map(|a| grid.face_dims(a).as_u64vec3().element_product())
            .sum();
        let cell_count = grid.cell_count() as u64;
        // Velocity x2, face kinds, pressure x2, divergence, solid cells: 4 bytes each.
        gpu.check_fits(
            &format!(
                "the {}x{}x{} wind grid",
                grid.cells.x, grid.cells.y, grid.cells.z
            ),
            4 * (3 * face_count + 4 * cell_count),
        )?;
        let (face_count, cell_count) = match (u32::try_from(face_count), u32::try_from(cell_count))
        {
            (Ok(f), Ok(c)) => (f, c),
            _ => {
                return Err(Error::InvalidInput(
                    "wind grid too large for 32-bit indices".into(),
                ))
            }
        };
        let gpu_sources = settings
            .sources
            .iter()
            .map(GpuWindSource::from_source)
            .collect::<Result<Vec<_>>>()?;
        let field = WindField::new(grid, settings);
        let buffers =
            WindBuffers::new(gpu, commands, &field, &gpu_sources, face_count, cell_count)?;
        let kernels = match WindKernels::new(gpu) {
            Ok(k) => k,
            Err(e) => {
                buffers.destroy(gpu);
                return Err(e);
            }
        };
        let set = match BufferSet::new(
            gpu,
            kernels.set_layout,
            WIND_SET,
            &buffers.raw(),
            "wind descriptor set",
        ) {
            Ok(s) => s,
            Err(e) => {
                kernels.destroy(gpu);
                buffers.destroy(gpu);
                return Err(e);
            }
        };
        Ok(Self {
            grid,
            settings: settings.clone(),
            buffers,
            kernels,
            set,
            face_count,
            cell_count,
        })
    }

    fn push(&self, time: f32, dt: f32, control: [u32; 4]) -> WindPush {
        let inflow = self.settings.inflow;
        let phases = inflow.map(|i| i.gust.phases()).unwrap_or_default();
        WindPush {
            cells: [
                self.grid.cells.x,
                self.grid.cells.y,
                self.grid.cells.z,
                self.face_count,
            ],
            origin: self.grid.origin.extend(0.0).to_array(),
            cell_size: self.grid.cell.extend(0.0).to_array(),
            step: [time, dt, 0.0, 0.0],
            control,
            inflow: inflow
                .map(|i| [i.speed, i.gust.amplitude, i.gust.frequency, 0.0])
                .unwrap_or_default(),
            inflow_phases: [phases[0], phases[1], phases[2], 0.0],
        }
    }

    /// Records one solver step at simulation time `time` into `cmd`. Ends
    /// with the new velocity (copy A) written by compute; a reader must
    /// wait on COMPUTE_SHADER writes.
    pub fn record_step(&self, gpu: &Gpu, cmd: vk::CommandBuffer, time: f32, dt: f32) {
        let device = &gpu.device.raw;
        let sources = self.settings.sources.len() as u32;
        let iterations = self.settings.jacobi_iterations;
        let result_half = iterations % 2;
        let face_groups = self.face_count.div_ceil(LOCAL_SIZE);
        let cell_groups = self.cell_count.div_ceil(LOCAL_SIZE);
        let dispatch = |kernel: usize, groups: u32, control: [u32; 4]| {
            let push = self.push(time, dt, control);
            // SAFETY: recording; pipeline, layout and set are ours and alive.
            unsafe {
                device.cmd_bind_pipeline(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.kernels.pipelines[kernel],
                );
                device.cmd_push_constants(
                    cmd,
                    self.kernels.layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    bytemuck::bytes_of(&push),
                );
                device.cmd_dispatch(cmd, groups, 1, 1);
            }
        };
        let control = |read: u32| [sources, read, result_half, 0];
        // SAFETY: recording; the set matches the layout.
        unsafe {
            // Whatever read or wrote the wind before (the previous step, the
            // grass sampling it) finishes first.
            compute_barrier(gpu, cmd, vk::PipelineStageFlags2::ALL_COMMANDS);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.kernels.layout,
                0,
                &[self.set.set],
                &[],
            );
        }
        dispatch(FORCES, face_groups, control(0));
        compute_barrier(gpu, cmd, vk::PipelineStageFlags2::COMPUTE_SHADER);
        dispatch(ADVECT, face_groups, control(0));
        compute_barrier(gpu, cmd, vk::PipelineStageFlags2::COMPUTE_SHADER);
        dispatch(DIVERGENCE, cell_groups, control(0));
        compute_barrier(gpu, cmd, vk::PipelineStageFlags2::COMPUTE_SHADER);
        for i in 0..iterations {
            dispatch(JACOBI, cell_groups, control(i % 2));
            compute_barrier(gpu, cmd, vk::PipelineStageFlags2::COMPUTE_SHADER);
        }
        dispatch(PROJECT, face_groups, control(0));
    }

    /// Copies the velocity (copy A: x, y, z components) back to the host:
    /// for tests, pictures and statistics, not per frame.
    pub fn read_velocity(&self, gpu: &Gpu, commands: &Commands) -> Result<[Vec<f32>; 3]> {
        let all: Vec<f32> =
            self.buffers
                .velocity
                .read_back(gpu, commands, self.face_count as usize)?;
        let mut split = [Vec::new(), Vec::new(), Vec::new()];
        let mut start = 0;
        for (axis, dst) in split.iter_mut().enumerate() {
            let d = self.grid.face_dims(axis);
            let n = (d.x * d.y * d.z) as usize;
            *dst = all[start..start + n].to_vec();
            start += n;
        }
        Ok(split)
    }

    /// The divergence of the last step's advected field, before projection.
    pub fn read_divergence(&self, gpu: &Gpu, commands: &Commands) -> Result<Vec<f32>> {
        self.buffers
            .divergence
            .read_back(gpu, commands, self.cell_count as usize)
    }

    /// The velocity buffer: copy A (the state between steps) starts at 0,
    /// in the layout of glsl/common/wind_grid.glsl. The grass samples it.
    pub fn velocity(&self) -> &Buffer {
        &self.buffers.velocity
    }

    pub fn destroy(self, gpu: &Gpu) {
        self.set.destroy(gpu);
        self.kernels.destroy(gpu);
        self.buffers.destroy(gpu);
    }
}

/// Every earlier write in `src` is visible to the compute shaders after it.
fn compute_barrier(gpu: &Gpu, cmd: vk::CommandBuffer, src: vk::PipelineStageFlags2) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src)
        .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::MEMORY_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
        .dst_access_mask(
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        )];
    // SAFETY: recording into a live command buffer.
    unsafe {
        gpu.device.raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&barrier),
        );
    }
}
