//! The SPIR-V of every shader under `glsl/`, compiled by build.rs and
//! embedded in the binary, plus binding reflection for the layout tests.

use ash::vk;

/// The pipeline stage a GLSL file is compiled for (from its extension).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShaderStage {
    Vertex,
    TessellationControl,
    TessellationEvaluation,
    Geometry,
    Fragment,
    Compute,
}

impl ShaderStage {
    pub fn vk(self) -> vk::ShaderStageFlags {
        match self {
            ShaderStage::Vertex => vk::ShaderStageFlags::VERTEX,
            ShaderStage::TessellationControl => vk::ShaderStageFlags::TESSELLATION_CONTROL,
            ShaderStage::TessellationEvaluation => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
            ShaderStage::Geometry => vk::ShaderStageFlags::GEOMETRY,
            ShaderStage::Fragment => vk::ShaderStageFlags::FRAGMENT,
            ShaderStage::Compute => vk::ShaderStageFlags::COMPUTE,
        }
    }

    /// naga's SPIR-V front end reads these stages; the others are
    /// reflected by `reflect::scan_bindings` alone.
    pub fn naga_supported(self) -> bool {
        matches!(
            self,
            ShaderStage::Vertex | ShaderStage::Fragment | ShaderStage::Compute
        )
    }
}

/// One embedded SPIR-V module.
#[derive(Clone, Copy, Debug)]
pub struct Spirv {
    /// Path under `glsl/`, e.g. "blade/blade.tesc".
    pub path: &'static str,
    pub stage: ShaderStage,
    pub bytes: &'static [u8],
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
