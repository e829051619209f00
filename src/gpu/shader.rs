//! Shader modules from the SPIR-V that build.rs compiled and embedded.

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::Gpu;
use crate::shaders::Spirv;

pub fn words(spirv: &Spirv) -> Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(spirv.bytes))
        .map_err(|e| Error::InvalidInput(format!("embedded SPIR-V {} is corrupt: {e}", spirv.path)))
}

pub fn module(gpu: &Gpu, spirv: &Spirv) -> Result<vk::ShaderModule> {
    let code = words(spirv)?;
    let info = vk::ShaderModuleCreateInfo::default().code(&code);
    // SAFETY: the SPIR-V came from glslang and was validated at build time.
    let module = unsafe { gpu.device.raw.create_shader_module(&info, None) }
        .vk_context("vkCreateShaderModule", spirv.path)?;
    gpu.device.name(module, spirv.path);
    Ok(module)
}
