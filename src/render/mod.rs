//! The GPU side of both phases: the simulation passes (wind, grass) and the
//! rendering (pipelines, targets, frame orchestration).

pub mod floor;
pub mod frame;
pub mod frame_uniforms;
pub mod grass_pass;
pub mod pipelines;
pub mod shadow;
pub mod simulation;
pub mod targets;
pub mod texture_maps;
pub mod textures;
pub mod wind_pass;
pub mod wind_slices;

pub use frame::{Frame, Renderer};
pub use frame_uniforms::{FrameUniforms, ViewMode};
