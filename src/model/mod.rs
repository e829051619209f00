//! CPU models of the paper: the grass model, and the CPU references of the
//! wind solver and the blade dynamics that the GPU compute shaders are
//! tested against.

pub mod blade;
pub mod canopy;
pub mod collider;
pub mod contact;
pub mod grass;
pub mod grass_field;
pub mod hash;

pub use blade::{has_width, Blade, BladeKind, BladeVertex, EdgeFrame};
pub use grass::{BladePhysics, GrassBlade, GrassState};
pub use grass_field::GrassField;
pub mod multigrid;
pub mod path;
pub mod quasi_static;
pub mod terrain;
pub mod turbulence;
pub mod wind;
