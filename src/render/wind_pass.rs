//! The wind solver on GPU compute (paper section 3.2): five kernels in
//! glsl/wind/, recorded into the frame's command buffer with a barrier
//! between each. All buffers are made once; a step allocates and uploads
//! nothing (the time and Jacobi parity travel as push constants).
//!
//! Obstacle voxelisation and the classification of every face (free, wall,
//! inflow) happen once on the CPU through `sim::wind::WindField`, the same
//! code the CPU reference steps with, and are uploaded.

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::commands::Commands;
use crate::gpu::{shader, Buffer, Gpu, MemoryLocation};
use crate::reflect::DescriptorKind;
use crate::render::pipelines::{create_set_layout, LayoutBinding};
use crate::shaders::{self, Spirv};
use crate::sim::wind::{FaceKind, WindField, WindGrid, WindSettings, WindSource};

/// Waypoints a source's path may have on the GPU.
pub const MAX_PATH_POINTS: usize = 8;
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
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
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
    storage(0), // velocity (two copies)
    storage(1), // face kinds
    storage(2), // solid cells
    storage(3), // pressure (two copies)
    storage(4), // divergence
    storage(5), // sources
];

const fn storage(binding: u32) -> LayoutBinding {
    LayoutBinding {
        set: 0,
        binding,
        ty: DescriptorKind::StorageBuffer,
        stages: vk::ShaderStageFlags::COMPUTE,
    }
}

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

pub struct WindPass {
    pub grid: WindGrid,
    settings: WindSettings,
    /// Velocity, two copies of every face: A (state) then B (advected).
    pub velocity: Buffer,
    faces: Buffer,
    solid: Buffer,
    pressure: Buffer,
    divergence: Buffer,
    sources: Buffer,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    pipelines: Vec<vk::Pipeline>,
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
        let field = WindField::new(grid, settings);
        let gpu_sources = settings
            .sources
            .iter()
            .map(GpuWindSource::from_source)
            .collect::<Result<Vec<_>>>()?;
        let mut created: Vec<Buffer> = Vec::new();
        let result = Self::build(
            gpu,
            commands,
            &field,
            settings,
            &gpu_sources,
            face_count,
            cell_count,
            &mut created,
        );
        match result {
            Ok(p) => Ok(p),
            Err(e) => {
                for b in created {
                    b.destroy(gpu);
                }
                Err(e)
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        gpu: &Gpu,
        commands: &Commands,
        field: &WindField,
        settings: &WindSettings,
        gpu_sources: &[GpuWindSource],
        face_count: u32,
        cell_count: u32,
        created: &mut Vec<Buffer>,
    ) -> Result<Self> {
        let device = &gpu.device.raw;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let read = vk::AccessFlags2::SHADER_STORAGE_READ;
        let kinds = field.faces.iter().flatten().map(|k| match k {
            FaceKind::Free => 0,
            FaceKind::Wall => 1,
            FaceKind::Inflow => 2,
        });
        created.push(Buffer::with_data(
            gpu,
            commands,
            "wind face kinds",
            &u32_bytes(kinds),
            storage,
            compute,
            read,
        )?);
        let solid = field.solid.iter().map(|&s| s as u32);
        created.push(Buffer::with_data(
            gpu,
            commands,
            "wind solid cells",
            &u32_bytes(solid),
            storage,
            compute,
            read,
        )?);
        // At least one entry so the binding is never empty.
        let sources_bytes: Vec<u8> = if gpu_sources.is_empty() {
            bytemuck::bytes_of(&GpuWindSource::default()).to_vec()
        } else {
            bytemuck::cast_slice(gpu_sources).to_vec()
        };
        created.push(Buffer::with_data(
            gpu,
            commands,
            "wind sources",
            &sources_bytes,
            storage,
            compute,
            read,
        )?);
        let rw = storage | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
        let f32_size = 4u64;
        created.push(Buffer::new(
            gpu,
            "wind velocity (A, B)",
            2 * face_count as u64 * f32_size,
            rw,
            MemoryLocation::GpuOnly,
        )?);
        created.push(Buffer::new(
            gpu,
            "wind pressure (ping, pong)",
            2 * cell_count as u64 * f32_size,
            rw,
            MemoryLocation::GpuOnly,
        )?);
        created.push(Buffer::new(
            gpu,
            "wind divergence",
            cell_count as u64 * f32_size,
            rw,
            MemoryLocation::GpuOnly,
        )?);

        // Zero the velocity once: the air starts at rest.
        let cmd = commands.begin(gpu)?;
        let velocity_raw = created[3].raw;
        let zeroed = [vk::BufferMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(compute)
            .dst_access_mask(read | vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .buffer(velocity_raw)
            .offset(0)
            .size(vk::WHOLE_SIZE)];
        // SAFETY: recording into our command buffer; the buffer is live.
        unsafe {
            device.cmd_fill_buffer(cmd, velocity_raw, 0, vk::WHOLE_SIZE, 0);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().buffer_memory_barriers(&zeroed),
            );
        }
        commands.submit_and_wait(gpu, "clearing the wind")?;

        let set_layout = create_set_layout(gpu, WIND_SET, "wind set layout")?;
        let push_range = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::COMPUTE,
            offset: 0,
            size: std::mem::size_of::<WindPush>() as u32,
        }];
        let set_layouts = [set_layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&push_range);
        // SAFETY: valid create info on a live device.
        let layout = match unsafe { device.create_pipeline_layout(&layout_info, None) } {
            Ok(l) => l,
            Err(r) => {
                unsafe { device.destroy_descriptor_set_layout(set_layout, None) };
                return Err(Error::vk(
                    "vkCreatePipelineLayout",
                    "wind pipeline layout",
                    r,
                ));
            }
        };
        gpu.device.name(layout, "wind pipeline layout");
        let destroy_layouts = || unsafe {
            device.destroy_pipeline_layout(layout, None);
            device.destroy_descriptor_set_layout(set_layout, None);
        };

        let mut pipelines = Vec::new();
        for spirv in WIND_KERNELS {
            match compute_pipeline(gpu, layout, spirv) {
                Ok(p) => pipelines.push(p),
                Err(e) => {
                    for p in pipelines {
                        unsafe { device.destroy_pipeline(p, None) };
                    }
                    destroy_layouts();
                    return Err(e);
                }
            }
        }
        let pool_sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::STORAGE_BUFFER,
            descriptor_count: WIND_SET.len() as u32,
        }];
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&pool_sizes);
        let pool = match unsafe { device.create_descriptor_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(r) => {
                for p in pipelines {
                    unsafe { device.destroy_pipeline(p, None) };
                }
                destroy_layouts();
                return Err(Error::vk("vkCreateDescriptorPool", "wind descriptors", r));
            }
        };
        gpu.device.name(pool, "wind descriptor pool");
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&set_layouts);
        // SAFETY: the pool has room for exactly this set.
        let set = unsafe { device.allocate_descriptor_sets(&alloc) }
            .vk_context("vkAllocateDescriptorSets", "wind set")?[0];
        gpu.device.name(set, "wind descriptor set");

        let mut drained = std::mem::take(created).into_iter();
        let mut next = || drained.next().expect("six wind buffers");
        let (faces, solid, sources, velocity, pressure, divergence) =
            (next(), next(), next(), next(), next(), next());
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> =
            [&velocity, &faces, &solid, &pressure, &divergence, &sources]
                .iter()
                .map(|b| {
                    [vk::DescriptorBufferInfo {
                        buffer: b.raw,
                        offset: 0,
                        range: vk::WHOLE_SIZE,
                    }]
                })
                .collect();
        let writes: Vec<_> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(i as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set is not in use by any command buffer yet.
        unsafe { device.update_descriptor_sets(&writes, &[]) };

        Ok(Self {
            grid: field.grid,
            settings: settings.clone(),
            velocity,
            faces,
            solid,
            pressure,
            divergence,
            sources,
            set_layout,
            layout,
            pool,
            set,
            pipelines,
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
                    self.pipelines[kernel],
                );
                device.cmd_push_constants(
                    cmd,
                    self.layout,
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
                self.layout,
                0,
                &[self.set],
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
        let all = read_floats(gpu, commands, &self.velocity, self.face_count as usize)?;
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
        read_floats(gpu, commands, &self.divergence, self.cell_count as usize)
    }

    pub fn destroy(self, gpu: &Gpu) {
        let device = &gpu.device.raw;
        // SAFETY: the owner waited for the GPU to finish with the pass.
        unsafe {
            for p in self.pipelines {
                device.destroy_pipeline(p, None);
            }
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
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

/// Copies the first `count` floats of a device buffer written by compute
/// into host memory.
fn read_floats(gpu: &Gpu, commands: &Commands, src: &Buffer, count: usize) -> Result<Vec<f32>> {
    let bytes = count as u64 * 4;
    let host = Buffer::new(
        gpu,
        "wind readback",
        bytes,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let result = (|| {
        let cmd = commands.begin(gpu)?;
        let to_copy = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)];
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: bytes,
        };
        // SAFETY: recording; both buffers live and large enough.
        unsafe {
            let device = &gpu.device.raw;
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&to_copy),
            );
            device.cmd_copy_buffer(cmd, src.raw, host.raw, &[region]);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&to_host),
            );
        }
        commands.submit_and_wait(gpu, "reading the wind back")
    })();
    let out = result.map(|()| bytemuck::cast_slice(host.mapped().expect("host-visible")).to_vec());
    host.destroy(gpu);
    out
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

fn compute_pipeline(gpu: &Gpu, layout: vk::PipelineLayout, spirv: &Spirv) -> Result<vk::Pipeline> {
    let device = &gpu.device.raw;
    let module = shader::module(gpu, spirv)?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout);
    // SAFETY: valid create info; the module is destroyed after creation.
    let result =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
    unsafe { device.destroy_shader_module(module, None) };
    let pipeline =
        result.map_err(|(_, r)| Error::vk("vkCreateComputePipelines", spirv.path, r))?[0];
    gpu.device.name(pipeline, spirv.path);
    Ok(pipeline)
}
