//! CPU models of the paper: the grass model (and, as they land, the CPU
//! references of the wind solver and the blade dynamics that the GPU
//! compute shaders are tested against).

pub mod blade;

pub use blade::{Blade, BladeKind, BladeVertex, EdgeFrame};
pub mod wind;
