//! The graphics pipelines of the colour pass: the blade pipeline with all
//! five stages of the paper (vertex -> tessellation control -> tessellation
//! evaluation -> geometry -> fragment), and the sky and ground behind it.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::descriptors::{create_pipeline_layout, create_set_layout, LayoutBinding};
use crate::gpu::{shader, Gpu};
use crate::reflect::DescriptorKind;
use crate::shaders::{self, Spirv};
use crate::sim::BladeVertex;

/// Set 0 of every render pipeline: the per-frame uniforms, the sun's
/// shadow map, and the grass and soil textures (the last five read by the
/// fragment stages of the colour pass). Images and samplers are bound apart
/// (glsl/common/shadow.glsl says why).
pub const FRAME_SET: &[LayoutBinding] = &[
    LayoutBinding {
        set: 0,
        binding: 0,
        ty: DescriptorKind::UniformBuffer,
        stages: vk::ShaderStageFlags::from_raw(
            vk::ShaderStageFlags::VERTEX.as_raw()
                | vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw()
                | vk::ShaderStageFlags::TESSELLATION_EVALUATION.as_raw()
                | vk::ShaderStageFlags::GEOMETRY.as_raw()
                | vk::ShaderStageFlags::FRAGMENT.as_raw(),
        ),
    },
    LayoutBinding {
        set: 0,
        binding: 1,
        ty: DescriptorKind::SampledImage,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
    LayoutBinding {
        set: 0,
        binding: 2,
        ty: DescriptorKind::Sampler,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
    LayoutBinding {
        set: 0,
        binding: 3,
        ty: DescriptorKind::SampledImage,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
    LayoutBinding {
        set: 0,
        binding: 4,
        ty: DescriptorKind::SampledImage,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
    LayoutBinding {
        set: 0,
        binding: 5,
        ty: DescriptorKind::Sampler,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
];

/// Set 0 of the shadow pass: the light's uniforms alone. A layout of its
/// own rather than the frame set partly written: the depth-only pipeline
/// reads nothing else, and lavapipe crashes drawing with a bound set whose
/// unused image bindings were never written (legal Vulkan, but nothing is
/// gained by it).
pub const SHADOW_SET: &[LayoutBinding] = FRAME_SET.split_at(1).0;

/// The shaders of each pipeline, for creation and for the reflection test.
pub const BLADE_STAGES: &[&Spirv] = &[
    &shaders::BLADE_BLADE_VERT,
    &shaders::BLADE_BLADE_TESC,
    &shaders::BLADE_BLADE_TESE,
    &shaders::BLADE_BLADE_GEOM,
    &shaders::BLADE_BLADE_FRAG,
];
/// The shadow pass draws the blades through the same stages up to the
/// geometry shader (their real deformed shape and LOD), depth only.
pub const SHADOW_STAGES: &[&Spirv] = &[
    &shaders::BLADE_BLADE_VERT,
    &shaders::BLADE_BLADE_TESC,
    &shaders::BLADE_BLADE_TESE,
    &shaders::BLADE_BLADE_GEOM,
];
pub const SKY_STAGES: &[&Spirv] = &[&shaders::BACKDROP_SKY_VERT, &shaders::BACKDROP_SKY_FRAG];
pub const GROUND_STAGES: &[&Spirv] = &[
    &shaders::BACKDROP_GROUND_VERT,
    &shaders::BACKDROP_GROUND_FRAG,
];

/// The blade vertex buffer's layout: one `BladeVertex` per control point.
pub const BLADE_ATTRIBUTES: [vk::VertexInputAttributeDescription; 2] = [
    vk::VertexInputAttributeDescription {
        location: 0,
        binding: 0,
        format: vk::Format::R32G32B32A32_SFLOAT,
        offset: std::mem::offset_of!(BladeVertex, position) as u32,
    },
    vk::VertexInputAttributeDescription {
        location: 1,
        binding: 0,
        format: vk::Format::R32G32B32A32_SFLOAT,
        offset: std::mem::offset_of!(BladeVertex, width) as u32,
    },
];

/// Formats and sample count the pipelines render into.
#[derive(Clone, Copy, Debug)]
pub struct TargetFormats {
    pub color: vk::Format,
    pub depth: vk::Format,
    pub samples: vk::SampleCountFlags,
}

pub struct RenderPipelines {
    pub set_layout: vk::DescriptorSetLayout,
    pub layout: vk::PipelineLayout,
    pub shadow_set_layout: vk::DescriptorSetLayout,
    pub shadow_layout: vk::PipelineLayout,
    pub blade: vk::Pipeline,
    /// Depth-only blades into the shadow map (None when shadows are off).
    pub shadow: Option<vk::Pipeline>,
    pub sky: vk::Pipeline,
    pub ground: vk::Pipeline,
}

/// The fixed-function choices that differ between our pipelines.
pub(crate) struct PipelineDesc<'a> {
    pub name: &'a str,
    pub stages: &'a [&'a Spirv],
    pub topology: vk::PrimitiveTopology,
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    pub patch_control_points: u32,
    pub depth_test: bool,
    /// Render into the shadow map: no colour, one sample, depth bias.
    pub shadow: bool,
}

impl RenderPipelines {
    pub fn new(gpu: &Gpu, formats: TargetFormats, shadows: bool) -> Result<Self> {
        let device = &gpu.device.raw;
        let (set_layout, layout) = layouts(gpu, FRAME_SET, "frame")?;
        let (shadow_set_layout, shadow_layout) = match layouts(gpu, SHADOW_SET, "shadow pass") {
            Ok(l) => l,
            Err(e) => {
                destroy_layouts(gpu, set_layout, layout);
                return Err(e);
            }
        };

        let blade_binding = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<BladeVertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let descs = [
            PipelineDesc {
                name: "blade pipeline (vert/tesc/tese/geom/frag)",
                stages: BLADE_STAGES,
                topology: vk::PrimitiveTopology::PATCH_LIST,
                vertex_bindings: &blade_binding,
                vertex_attributes: &BLADE_ATTRIBUTES,
                patch_control_points: 4,
                depth_test: true,
                shadow: false,
            },
            PipelineDesc {
                name: "sky pipeline",
                stages: SKY_STAGES,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: 0,
                depth_test: false,
                shadow: false,
            },
            PipelineDesc {
                name: "ground pipeline",
                stages: GROUND_STAGES,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: 0,
                depth_test: true,
                shadow: false,
            },
            PipelineDesc {
                name: "shadow pipeline (vert/tesc/tese/geom, depth only)",
                stages: SHADOW_STAGES,
                topology: vk::PrimitiveTopology::PATCH_LIST,
                vertex_bindings: &blade_binding,
                vertex_attributes: &BLADE_ATTRIBUTES,
                patch_control_points: 4,
                depth_test: true,
                shadow: true,
            },
        ];
        let descs = if shadows { &descs[..] } else { &descs[..3] };
        let mut pipelines = Vec::new();
        for desc in descs {
            let pipeline_layout = if desc.shadow { shadow_layout } else { layout };
            match create_pipeline(gpu, pipeline_layout, formats, desc) {
                Ok(p) => pipelines.push(p),
                Err(e) => {
                    // SAFETY: nothing has used these pipelines yet.
                    unsafe {
                        for p in pipelines {
                            device.destroy_pipeline(p, None);
                        }
                    }
                    destroy_layouts(gpu, shadow_set_layout, shadow_layout);
                    destroy_layouts(gpu, set_layout, layout);
                    return Err(e);
                }
            }
        }
        Ok(Self {
            set_layout,
            layout,
            shadow_set_layout,
            shadow_layout,
            blade: pipelines[0],
            sky: pipelines[1],
            ground: pipelines[2],
            shadow: pipelines.get(3).copied(),
        })
    }

    pub fn destroy(self, gpu: &Gpu) {
        let device = &gpu.device.raw;
        // SAFETY: the owner waited for the GPU to finish with these.
        unsafe {
            device.destroy_pipeline(self.blade, None);
            device.destroy_pipeline(self.sky, None);
            device.destroy_pipeline(self.ground, None);
            if let Some(p) = self.shadow {
                device.destroy_pipeline(p, None);
            }
        }
        destroy_layouts(gpu, self.shadow_set_layout, self.shadow_layout);
        destroy_layouts(gpu, self.set_layout, self.layout);
    }
}

/// A set layout of `bindings` and the pipeline layout of that one set.
fn layouts(
    gpu: &Gpu,
    bindings: &[LayoutBinding],
    name: &str,
) -> Result<(vk::DescriptorSetLayout, vk::PipelineLayout)> {
    let set_layout = create_set_layout(gpu, bindings, &format!("{name} set layout"))?;
    match create_pipeline_layout(gpu, set_layout, None, &format!("{name} pipeline layout")) {
        Ok(layout) => Ok((set_layout, layout)),
        Err(e) => {
            // SAFETY: nothing uses the set layout yet.
            unsafe {
                gpu.device
                    .raw
                    .destroy_descriptor_set_layout(set_layout, None)
            };
            Err(e)
        }
    }
}

fn destroy_layouts(gpu: &Gpu, set_layout: vk::DescriptorSetLayout, layout: vk::PipelineLayout) {
    // SAFETY: the owner guarantees no pipeline or command buffer in flight
    // still uses them.
    unsafe {
        gpu.device.raw.destroy_pipeline_layout(layout, None);
        gpu.device
            .raw
            .destroy_descriptor_set_layout(set_layout, None);
    }
}

pub(crate) fn create_pipeline(
    gpu: &Gpu,
    layout: vk::PipelineLayout,
    formats: TargetFormats,
    desc: &PipelineDesc,
) -> Result<vk::Pipeline> {
    let device = &gpu.device.raw;
    let mut modules = Vec::new();
    for spirv in desc.stages {
        match shader::module(gpu, spirv) {
            Ok(m) => modules.push(m),
            Err(e) => {
                for m in modules {
                    unsafe { device.destroy_shader_module(m, None) };
                }
                return Err(e);
            }
        }
    }
    let stage_infos: Vec<_> = desc
        .stages
        .iter()
        .zip(&modules)
        .map(|(spirv, &module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(spirv.stage.vk())
                .module(module)
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
    // Two-sided: blades are thin sheets seen from both sides; the fragment
    // stage flips the normal on back faces.
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    // The shadow map is single-sampled; its depth is pushed back by a
    // constant and a slope term so a blade does not shadow itself where it
    // is the occluder (shadow acne).
    let raster = if desc.shadow {
        raster
            .depth_bias_enable(true)
            .depth_bias_constant_factor(2.0)
            .depth_bias_slope_factor(2.5)
    } else {
        raster
    };
    let samples = if desc.shadow {
        vk::SampleCountFlags::TYPE_1
    } else {
        formats.samples
    };
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(samples);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(desc.depth_test)
        .depth_write_enable(desc.depth_test)
        .depth_compare_op(vk::CompareOp::LESS);
    let blend_attachments = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend_attachments: &[_] = if desc.shadow { &[] } else { &blend_attachments };
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = [formats.color];
    let color_formats: &[_] = if desc.shadow { &[] } else { &color_formats };
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(color_formats)
        .depth_attachment_format(if desc.shadow {
            super::shadow::SHADOW_FORMAT
        } else {
            formats.depth
        });

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
        .layout(layout)
        .push_next(&mut rendering);
    if desc.patch_control_points > 0 {
        info = info.tessellation_state(&tessellation);
    }
    // SAFETY: every referenced structure lives until the call returns.
    let result =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    // SAFETY: modules are no longer needed once the pipeline exists (or failed).
    for m in modules {
        unsafe { device.destroy_shader_module(m, None) };
    }
    let pipeline =
        result.map_err(|(_, r)| Error::vk("vkCreateGraphicsPipelines", desc.name, r))?[0];
    gpu.device.name(pipeline, desc.name);
    Ok(pipeline)
}
