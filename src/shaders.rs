//! The SPIR-V of every shader under `glsl/`, compiled by build.rs and
//! embedded in the binary, named after its file (`BLADE_BLADE_TESC` is
//! glsl/blade/blade.tesc).

use crate::gpu::shader::{BindingAccess, ShaderBinding};
pub use crate::gpu::shader::{ShaderStage, Spirv};
use crate::gpu::DescriptorKind;

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
