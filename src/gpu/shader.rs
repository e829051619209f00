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

/// A compute pipeline running `spirv`'s `main` with `layout`, named after
/// its source file.
pub fn compute_pipeline(
    gpu: &Gpu,
    layout: vk::PipelineLayout,
    spirv: &Spirv,
) -> Result<vk::Pipeline> {
    let device = &gpu.device.raw;
    let module = module(gpu, spirv)?;
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
