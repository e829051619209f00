//! The rendering phase (paper section 5): the paper's pipeline (vertex ->
//! tessellation control -> tessellation evaluation -> geometry ->
//! fragment), the cull pass that lists the blades each pass draws, the
//! shadow map, the obstacles, the surface textures, the render targets
//! and the read-back; and the bench's vertex+fragment floor. It draws the
//! blade buffer it is handed and knows nothing of the simulation.

pub mod canopy_map;
pub mod cull;
pub mod depth_pyramid;
pub mod floor;
pub mod frame_uniforms;
pub mod obstacles;
pub mod pipelines;
pub mod renderer;
pub mod shadow;
pub mod shadow_frustum;
pub mod shadow_params;
pub mod targets;
pub mod terrain;
pub mod texture_maps;
pub mod textures;
pub mod thinning;
pub mod visibility;

pub use frame_uniforms::{FrameUniforms, ViewMode};
pub use renderer::Renderer;
