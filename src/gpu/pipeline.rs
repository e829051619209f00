//! Compute and graphics pipelines, each made with a `PipelineLayout`.

use std::sync::Arc;

use ash::vk;
use ash::vk::Handle;

use crate::error::{Error, Result};
use crate::gpu::descriptors::PipelineLayout;
use crate::gpu::owned::Owned;
use crate::gpu::shader::{self, Spirv};
use crate::gpu::Gpu;

/// Formats and sample count a graphics pipeline renders into.
#[derive(Clone, Copy, Debug)]
pub struct TargetFormats {
    /// None: depth only.
    pub color: Option<vk::Format>,
    pub depth: vk::Format,
    pub samples: vk::SampleCountFlags,
}

/// The fixed-function choices that differ between meadow's graphics
/// pipelines, all with dynamic viewport and scissor. Faces wind
/// counter-clockwise.
pub struct GraphicsDesc<'a> {
    pub name: &'a str,
    pub stages: &'a [&'a Spirv],
    pub topology: vk::PrimitiveTopology,
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// Control points per patch; 0 without tessellation.
    pub patch_control_points: u32,
    pub depth_test: bool,
    /// Constant and slope depth bias (shadow maps), or none.
    pub depth_bias: Option<(f32, f32)>,
    /// The faces not drawn: NONE for two-sided (blades are thin sheets
    /// seen from both sides).
    pub cull: vk::CullModeFlags,
    pub targets: TargetFormats,
}

/// A compute pipeline as the GPU keeps it (made once): its layout's
/// handle, its SPIR-V's address and length (a static of build.rs's), and
/// its (constant id, value) pairs.
#[derive(PartialEq, Eq, Hash)]
pub(super) struct ComputeKey {
    layout: u64,
    spirv: (usize, usize),
    constants: Vec<(u32, u32)>,
}

impl ComputeKey {
    fn new(layout: &PipelineLayout, spirv: &'static [u8], constants: &[(u32, u32)]) -> Self {
        Self {
            layout: layout.raw().as_raw(),
            spirv: (spirv.as_ptr() as usize, spirv.len()),
            constants: constants.to_vec(),
        }
    }
}

/// A pipeline and its layout; a clone shares the handle (compute
/// pipelines are made once per device, `gpu::made_once`).
#[derive(Clone)]
pub struct Pipeline {
    pub(super) layout: Arc<PipelineLayout>,
    raw: Arc<Owned<vk::Pipeline>>,
    pub(super) bind_point: vk::PipelineBindPoint,
}

impl Pipeline {
    pub(super) fn raw(&self) -> vk::Pipeline {
        self.raw.raw()
    }

    /// A compute pipeline running `spirv`'s `main`, named after its file.
    pub fn compute(gpu: &Gpu, layout: &Arc<PipelineLayout>, spirv: &Spirv) -> Result<Self> {
        Self::compute_specialized(gpu, layout, spirv, &[])
    }

    /// As `compute`, with each (id, value) of `constants` for the shader's
    /// specialization constant `constant_id = id` (each a 32-bit scalar).
    pub fn compute_specialized(
        gpu: &Gpu,
        layout: &Arc<PipelineLayout>,
        spirv: &Spirv,
        constants: &[(u32, u32)],
    ) -> Result<Self> {
        let key = ComputeKey::new(layout, spirv.bytes, constants);
        gpu.compute
            .get(key, || Self::compute_made(gpu, layout, spirv, constants))
    }

    /// A new compute pipeline, as `compute_specialized` describes it.
    fn compute_made(
        gpu: &Gpu,
        layout: &Arc<PipelineLayout>,
        spirv: &Spirv,
        constants: &[(u32, u32)],
    ) -> Result<Self> {
        let device = gpu.device();
        let module = shader::module(gpu, spirv)?;
        let entries: Vec<vk::SpecializationMapEntry> = (0..constants.len() as u32)
            .map(|i| {
                vk::SpecializationMapEntry::default()
                    .constant_id(constants[i as usize].0)
                    .offset(4 * i)
                    .size(4)
            })
            .collect();
        let values: Vec<u32> = constants.iter().map(|&(_, value)| value).collect();
        let data: &[u8] = bytemuck::cast_slice(&values);
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(data);
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw())
            .name(c"main");
        if !constants.is_empty() {
            stage = stage.specialization_info(&specialization);
        }
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.raw());
        // SAFETY: a valid create info whose module and layout are live.
        let raw = unsafe {
            device
                .raw
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, r)| Error::vk("vkCreateComputePipelines", spirv.path, r))?[0];
        Ok(Self {
            layout: layout.clone(),
            raw: Arc::new(Owned::new(device, raw, spirv.path)),
            bind_point: vk::PipelineBindPoint::COMPUTE,
        })
    }

    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn graphics(gpu: &Gpu, layout: &Arc<PipelineLayout>, desc: &GraphicsDesc) -> Result<Self> {
        let device = gpu.device();
        let modules = desc
            .stages
            .iter()
            .map(|spirv| shader::module(gpu, spirv))
            .collect::<Result<Vec<_>>>()?;
        let stage_infos: Vec<_> = desc
            .stages
            .iter()
            .zip(&modules)
            .map(|(spirv, module)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(spirv.stage.vk())
                    .module(module.raw())
                    .name(c"main")
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(desc.vertex_bindings)
            .vertex_attribute_descriptions(desc.vertex_attributes);
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let tessellation = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(desc.patch_control_points);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(desc.cull)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let raster = match desc.depth_bias {
            Some((constant, slope)) => raster
                .depth_bias_enable(true)
                .depth_bias_constant_factor(constant)
                .depth_bias_slope_factor(slope),
            None => raster,
        };
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(desc.targets.samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth_test)
            .depth_write_enable(desc.depth_test)
            .depth_compare_op(vk::CompareOp::LESS);
        let color_formats: Vec<vk::Format> = desc.targets.color.into_iter().collect();
        let blend_attachments: Vec<_> = color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA)
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(desc.targets.depth);
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stage_infos)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.raw())
            .push_next(&mut rendering);
        if desc.patch_control_points > 0 {
            info = info.tessellation_state(&tessellation);
        }
        // SAFETY: every structure the info points at lives until the call
        // returns; the modules and the layout are live.
        let raw = unsafe {
            device
                .raw
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, r)| Error::vk("vkCreateGraphicsPipelines", desc.name, r))?[0];
        Ok(Self {
            layout: layout.clone(),
            raw: Arc::new(Owned::new(device, raw, desc.name)),
            bind_point: vk::PipelineBindPoint::GRAPHICS,
        })
    }
}
