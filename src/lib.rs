//! meadow: the grass-swaying method of Lee, Lo, Chu and Chang, "A simulation
//! on grass swaying with dynamic wind force" (The Visual Computer, 2016), on
//! raw Vulkan.
//!
//! - `gpu`: instance, device, memory, buffers, images, commands, queries.
//! - `scene`: scenes and the grass field generator.
//! - `sim`: the grass model (and CPU references of the simulation).
//! - `render`: the paper's render pipeline and frame orchestration.
//! - `shaders` / `reflect`: the embedded SPIR-V and its binding reflection.

pub mod error;
pub mod gpu;
pub mod job;
pub mod output;
pub mod reflect;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod sim;
pub mod wind_job;

pub use error::{Error, Result};
