//! The SPIR-V of every shader under `glsl/`, compiled by build.rs and
//! embedded in the binary, named after its file (`BLADE_BLADE_TESC` is
//! glsl/blade/blade.tesc).

pub use crate::gpu::shader::{ShaderStage, Spirv};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
