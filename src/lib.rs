//! meadow: the grass-swaying method of Lee, Lo, Chu and Chang, "A simulation
//! on grass swaying with dynamic wind force" (The Visual Computer, 2016), on
//! raw Vulkan.
//!
//! - `gpu`: instance, device, memory, buffers, images, commands, queries.
//! - `scene`: scenes and the grass field generator.
//! - `sim`: the grass model and the CPU references of the wind and the
//!   grass dynamics.
//! - `render`: the GPU passes of both phases (wind, grass, the paper's
//!   render pipeline) and frame orchestration.
//! - `job`, `wind_job`, `grass_job`: what the `meadow` commands run.
//! - `shaders` / `reflect`: the embedded SPIR-V and its binding reflection.

pub mod bench;
pub mod error;
pub mod gpu;
pub mod grass_job;
pub mod job;
pub mod output;
pub mod reflect;
pub mod render;
pub mod reproduce;
pub mod scene;
pub mod shaders;
pub mod sim;
pub mod wind_job;

pub use error::{Error, Result};
