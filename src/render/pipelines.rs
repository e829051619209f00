//! The graphics pipelines of the colour pass: the blade pipeline with all
//! five stages of the paper (vertex -> tessellation control -> tessellation
//! evaluation -> geometry -> fragment), the sky and ground behind it and the
//! obstacles among it; and the shadow pass's depth-only pipelines.

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::gpu::{
    DescriptorKind, Gpu, GraphicsDesc, LayoutBinding, Pipeline, PipelineLayout, TargetFormats,
};
use crate::model::BladeVertex;
use crate::render::obstacles::{ObstacleVertex, Placement};
use crate::render::terrain::TerrainVertex;
use crate::shaders::{self, Spirv};

/// Set 0 of every render pipeline: the per-frame uniforms, the sun's
/// shadow map, the grass and soil textures and the canopy map (the last
/// six read by the fragment stages of the colour pass). Images and samplers are bound apart
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
    LayoutBinding {
        set: 0,
        binding: 6,
        ty: DescriptorKind::SampledImage,
        stages: vk::ShaderStageFlags::FRAGMENT,
    },
];

/// Set 0 of the shadow pass: the light's uniforms alone. A layout of its
/// own rather than the frame set partly written: the depth-only pipeline
/// reads nothing else, and lavapipe crashes drawing with a bound set whose
/// unused image bindings were never written (legal Vulkan, but nothing is
/// gained by it).
pub const SHADOW_SET: &[LayoutBinding] = FRAME_SET.split_at(1).0;

/// The shadow map's format: depth only.
pub const SHADOW_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

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
/// Obstacles (paper Fig. 13): triangle meshes, shaded and shadowed.
pub const OBSTACLE_STAGES: &[&Spirv] = &[
    &shaders::OBSTACLE_OBSTACLE_VERT,
    &shaders::OBSTACLE_OBSTACLE_FRAG,
];
/// ... and into the shadow map, depth only.
pub const OBSTACLE_SHADOW_STAGES: &[&Spirv] = &[&shaders::OBSTACLE_OBSTACLE_VERT];
/// The terrain's mesh (src/render/terrain.rs): the soil, shaded and
/// shadowed.
pub const TERRAIN_STAGES: &[&Spirv] = &[
    &shaders::TERRAIN_TERRAIN_VERT,
    &shaders::TERRAIN_TERRAIN_FRAG,
];
/// ... and its faces away from the sun into the shadow map, depth only.
pub const TERRAIN_SHADOW_STAGES: &[&Spirv] = &[&shaders::TERRAIN_TERRAIN_VERT];
pub const GROUND_STAGES: &[&Spirv] = &[
    &shaders::BACKDROP_GROUND_VERT,
    &shaders::BACKDROP_GROUND_FRAG,
];

/// Attribute `location` of vertex buffer binding 0: `format` at `offset`.
const fn attribute(
    location: u32,
    format: vk::Format,
    offset: usize,
) -> vk::VertexInputAttributeDescription {
    vk::VertexInputAttributeDescription {
        location,
        binding: 0,
        format,
        offset: offset as u32,
    }
}

const VEC3: vk::Format = vk::Format::R32G32B32_SFLOAT;
const FLOAT: vk::Format = vk::Format::R32_SFLOAT;

/// The blade vertex buffer's layout: one `BladeVertex` per control point.
/// glsl/blade/blade.vert reads each field at the location of its order.
pub const BLADE_ATTRIBUTES: [vk::VertexInputAttributeDescription; 4] = [
    attribute(0, VEC3, std::mem::offset_of!(BladeVertex, position)),
    attribute(1, FLOAT, std::mem::offset_of!(BladeVertex, blade_rand)),
    attribute(2, VEC3, std::mem::offset_of!(BladeVertex, half_width)),
    attribute(3, FLOAT, std::mem::offset_of!(BladeVertex, displacement)),
];

/// The obstacle vertex buffer's layout: one `ObstacleVertex` per corner.
pub const OBSTACLE_ATTRIBUTES: [vk::VertexInputAttributeDescription; 3] = [
    attribute(0, VEC3, std::mem::offset_of!(ObstacleVertex, position)),
    attribute(1, VEC3, std::mem::offset_of!(ObstacleVertex, normal)),
    attribute(2, VEC3, std::mem::offset_of!(ObstacleVertex, albedo)),
];

/// The terrain vertex buffer's layout: one `TerrainVertex` per corner.
pub const TERRAIN_ATTRIBUTES: [vk::VertexInputAttributeDescription; 2] = [
    attribute(0, VEC3, std::mem::offset_of!(TerrainVertex, position)),
    attribute(1, VEC3, std::mem::offset_of!(TerrainVertex, normal)),
];

const TERRAIN_BINDING: [vk::VertexInputBindingDescription; 1] =
    [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<TerrainVertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];

const OBSTACLE_BINDING: [vk::VertexInputBindingDescription; 1] =
    [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<ObstacleVertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];

/// The depth bias of the shadow pass (constant, slope): pushes each
/// caster's depth back so a surface does not shadow itself (acne).
const SHADOW_DEPTH_BIAS: (f32, f32) = (2.0, 2.5);

/// The faces toward the sun, as the shadow pass rasterises them: its
/// projection (src/render/shadow_frustum.rs) keeps the sun's view y up,
/// where Vulkan's framebuffer runs down, so a face counter-clockwise
/// seen from the sun lands clockwise: back-facing.
const SUNLIT_FACES: vk::CullModeFlags = vk::CullModeFlags::BACK;

pub struct RenderPipelines {
    pub frame_layout: Arc<PipelineLayout>,
    pub shadow_layout: Arc<PipelineLayout>,
    pub blade: Pipeline,
    pub sky: Pipeline,
    pub ground: Pipeline,
    pub obstacle: Pipeline,
    pub terrain: Pipeline,
    /// Depth-only blades and obstacles into the shadow map (None when
    /// shadows are off).
    pub shadow: Option<ShadowPipelines>,
}

/// The shadow pass's two depth-only pipelines.
pub struct ShadowPipelines {
    pub blades: Pipeline,
    pub obstacles: Pipeline,
    /// The terrain's faces turned away from the sun.
    pub terrain: Pipeline,
}

const BLADE_BINDING: [vk::VertexInputBindingDescription; 1] = [vk::VertexInputBindingDescription {
    binding: 0,
    stride: std::mem::size_of::<BladeVertex>() as u32,
    input_rate: vk::VertexInputRate::VERTEX,
}];

impl RenderPipelines {
    /// The colour pass's pipelines for `targets`, and the shadow pass's
    /// when `shadows`.
    /// Long on purpose: one create-info after another, each object named
    /// and owned as it is made.
    pub fn new(gpu: &Gpu, targets: TargetFormats, shadows: bool) -> Result<Self> {
        // One layout for every pipeline of a pass, so the set bound once
        // serves them all; the obstacles' placement is its push constant.
        let vertex = vk::ShaderStageFlags::VERTEX;
        let frame_layout = PipelineLayout::new::<Placement>(gpu, FRAME_SET, vertex, "frame")?;
        let shadow_layout =
            PipelineLayout::new::<Placement>(gpu, SHADOW_SET, vertex, "shadow pass")?;
        let backdrop = |name, stages, depth_test| GraphicsDesc {
            name,
            stages,
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            vertex_bindings: &[],
            vertex_attributes: &[],
            patch_control_points: 0,
            depth_test,
            depth_bias: None,
            cull: vk::CullModeFlags::NONE,
            targets,
        };
        let blade = GraphicsDesc {
            name: "blade pipeline (vert/tesc/tese/geom/frag)",
            stages: BLADE_STAGES,
            topology: vk::PrimitiveTopology::PATCH_LIST,
            vertex_bindings: &BLADE_BINDING,
            vertex_attributes: &BLADE_ATTRIBUTES,
            patch_control_points: 4,
            depth_test: true,
            depth_bias: None,
            cull: vk::CullModeFlags::NONE,
            targets,
        };
        let obstacle = GraphicsDesc {
            name: "obstacle pipeline (vert/frag)",
            stages: OBSTACLE_STAGES,
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            vertex_bindings: &OBSTACLE_BINDING,
            vertex_attributes: &OBSTACLE_ATTRIBUTES,
            patch_control_points: 0,
            depth_test: true,
            depth_bias: None,
            cull: vk::CullModeFlags::NONE,
            targets,
        };
        let terrain = GraphicsDesc {
            name: "terrain pipeline (vert/frag)",
            stages: TERRAIN_STAGES,
            vertex_bindings: &TERRAIN_BINDING,
            vertex_attributes: &TERRAIN_ATTRIBUTES,
            ..obstacle
        };
        // The shadow map is single-sampled, depth only, its depth pushed back
        // so a caster does not shadow itself where it is the occluder.
        let shadow_targets = TargetFormats {
            color: None,
            depth: SHADOW_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
        };
        let shadow = shadows
            .then(|| -> Result<ShadowPipelines> {
                let blades = GraphicsDesc {
                    name: "shadow pipeline (vert/tesc/tese/geom, depth only)",
                    stages: SHADOW_STAGES,
                    depth_bias: Some(SHADOW_DEPTH_BIAS),
                    targets: shadow_targets,
                    ..blade
                };
                let obstacles = GraphicsDesc {
                    name: "obstacle shadow pipeline (vert, depth only)",
                    stages: OBSTACLE_SHADOW_STAGES,
                    depth_bias: Some(SHADOW_DEPTH_BIAS),
                    targets: shadow_targets,
                    ..obstacle
                };
                // The terrain's faces toward the sun are not drawn
                // (src/render/terrain.rs says why).
                let terrain = GraphicsDesc {
                    name: "terrain shadow pipeline (vert, depth only, faces away from the sun)",
                    stages: TERRAIN_SHADOW_STAGES,
                    cull: SUNLIT_FACES,
                    depth_bias: Some(SHADOW_DEPTH_BIAS),
                    targets: shadow_targets,
                    ..terrain
                };
                Ok(ShadowPipelines {
                    blades: Pipeline::graphics(gpu, &shadow_layout, &blades)?,
                    obstacles: Pipeline::graphics(gpu, &shadow_layout, &obstacles)?,
                    terrain: Pipeline::graphics(gpu, &shadow_layout, &terrain)?,
                })
            })
            .transpose()?;
        Ok(Self {
            blade: Pipeline::graphics(gpu, &frame_layout, &blade)?,
            sky: Pipeline::graphics(
                gpu,
                &frame_layout,
                &backdrop("sky pipeline", SKY_STAGES, false),
            )?,
            ground: Pipeline::graphics(
                gpu,
                &frame_layout,
                &backdrop("ground pipeline", GROUND_STAGES, true),
            )?,
            obstacle: Pipeline::graphics(gpu, &frame_layout, &obstacle)?,
            terrain: Pipeline::graphics(gpu, &frame_layout, &terrain)?,
            shadow,
            frame_layout,
            shadow_layout,
        })
    }
}
