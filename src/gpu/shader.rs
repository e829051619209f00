//! Shader modules from SPIR-V embedded in the binary (`crate::shaders`
//! holds meadow's, compiled by build.rs).

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::owned::Owned;
use crate::gpu::Gpu;

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

    /// naga's SPIR-V front end reads these stages; the reflection tests
    /// read the others' decorations directly.
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

impl Spirv {
    pub fn words(&self) -> Result<Vec<u32>> {
        ash::util::read_spv(&mut std::io::Cursor::new(self.bytes)).map_err(|e| {
            Error::InvalidInput(format!("embedded SPIR-V {} is corrupt: {e}", self.path))
        })
    }
}

/// A shader module, destroyed when the pipeline made from it exists.
pub(super) fn module(gpu: &Gpu, spirv: &Spirv) -> Result<Owned<vk::ShaderModule>> {
    let code = spirv.words()?;
    let info = vk::ShaderModuleCreateInfo::default().code(&code);
    let device = gpu.device();
    // SAFETY: the SPIR-V came from glslang and was validated at build time.
    let module = unsafe { device.raw.create_shader_module(&info, None) }
        .vk_context("vkCreateShaderModule", spirv.path)?;
    Ok(Owned::new(device, module, spirv.path))
}
