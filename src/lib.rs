//! meadow: the grass-swaying method of Lee, Lo, Chu and Chang, "A simulation
//! on grass swaying with dynamic wind force" (The Visual Computer, 2016), on
//! raw Vulkan. Layers, each importing only those below it:
//!
//! 1. `gpu`: Vulkan (the only `unsafe`), and `error`.
//! 2. `scene` and `model`: scenes, and the paper's model on the CPU (the
//!    reference the GPU is checked against); `shaders`, the embedded SPIR-V;
//!    `interface`, the push constants and constants Rust and GLSL share,
//!    written once (src/interface/defs.rs; build.rs writes the GLSL).
//! 3. `compute` (the simulating phase: wind and grass on GPU compute) and
//!    `render` (the paper's render pipeline, shadow map, targets,
//!    read-back): siblings.
//! 4. `frame`: the blade buffer both share, and the frame recorder.
//!    `analysis`: measurements of results as plain arithmetic (pixels,
//!    series), no GPU; it needs `interface` only.
//! 5. `report`: files, pictures, tables and charts from results.
//! 6. `commands`: one file per `meadow` command (the binary's src/cli/
//!    holds each one's arguments).
//!
//! docs/architecture.md has the map.

pub mod analysis;
pub mod commands;
pub mod compute;
pub mod error;
pub mod frame;
pub mod gpu;
pub mod interface;
pub mod model;
pub mod render;
pub mod report;
pub mod scene;
pub mod shaders;

pub use error::{Error, Result};
