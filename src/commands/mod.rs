//! What each `meadow` command runs, one file per command, as library calls
//! the binary and the tests share. Every command has the same skeleton:
//! check the request without a GPU, open the GPU (`on_gpu`), do the work,
//! tear the GPU down pairing the result with what validation said, write
//! the report, and only then fail on a validation error (so the report
//! that names it is on disk).

pub mod bench;
pub mod bench_grass;
pub mod devices;
pub mod gpu_report;
pub mod render;
pub mod reproduce;
pub mod scenes;
pub mod trace;
pub mod view;
pub mod wind;

use crate::error::Result;
use crate::gpu::{Gpu, GpuOptions, ValidationReport};

/// Opens the GPU, runs `work` on it, tears it down, and pairs the result
/// with what validation reported over the GPU's life.
pub fn on_gpu<T>(
    options: &GpuOptions,
    work: impl FnOnce(&Gpu) -> Result<T>,
) -> Result<(T, ValidationReport)> {
    let gpu = Gpu::new(options)?;
    let result = work(&gpu);
    gpu.finish(result)
}
