//! Pipeline layouts and compute pipelines made once per device: a pass
//! made again on the same `Gpu` (bench's rows and its solvers side by
//! side, the GPU report's parts, a renderer made again at a new size)
//! takes the ones already made instead of compiling its kernels again. On
//! lavapipe compiling is most of a short run: a wind pass's kernels take
//! about 0.25 s of CPU (its V-cycle's tail kernel 60 ms) even with Mesa's
//! disk cache, and bench made them four times.
//!
//! Both are immutable once made, so sharing one is sharing its handle; a
//! layout is found by what it declares (its bindings and push range), a
//! pipeline by its layout, its SPIR-V (a static of build.rs's, found by
//! address) and its specialisation constants. `Gpu::destroy` drops them
//! before it counts what is still alive.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use ash::vk::Handle;

use crate::error::Result;
use crate::gpu::descriptors::{DescriptorKind, PipelineLayout};
use crate::gpu::pipeline::Pipeline;

/// What a pipeline layout declares: each binding's (set, binding, kind,
/// stages), the push block's size and stages.
#[derive(Clone, PartialEq, Eq, Hash)]
pub(super) struct LayoutKey {
    pub bindings: Vec<(u32, u32, DescriptorKind, u32)>,
    pub push_size: u32,
    pub push_stages: u32,
}

/// A compute pipeline: its layout's handle, its SPIR-V's address and
/// length, and its (constant id, value) pairs.
#[derive(Clone, PartialEq, Eq, Hash)]
pub(super) struct ComputeKey {
    pub layout: u64,
    pub spirv: (usize, usize),
    pub constants: Vec<(u32, u32)>,
}

impl ComputeKey {
    pub fn new(layout: &PipelineLayout, spirv: &'static [u8], constants: &[(u32, u32)]) -> Self {
        Self {
            layout: layout.raw().as_raw(),
            spirv: (spirv.as_ptr() as usize, spirv.len()),
            constants: constants.to_vec(),
        }
    }
}

#[derive(Default)]
pub(super) struct MadeOnce {
    layouts: Mutex<HashMap<LayoutKey, Arc<PipelineLayout>>>,
    compute: Mutex<HashMap<ComputeKey, Pipeline>>,
    /// How many compute pipelines `make` has made.
    compute_made: AtomicUsize,
}

/// The map behind `lock`, whether or not a thread panicked holding it:
/// an entry is whole or absent (inserted after it is made).
fn lock<K, V>(map: &Mutex<HashMap<K, V>>) -> std::sync::MutexGuard<'_, HashMap<K, V>> {
    map.lock().unwrap_or_else(PoisonError::into_inner)
}

impl MadeOnce {
    /// The layout `key` declares, made by `make` the first time.
    pub fn layout(
        &self,
        key: LayoutKey,
        make: impl FnOnce() -> Result<Arc<PipelineLayout>>,
    ) -> Result<Arc<PipelineLayout>> {
        let mut layouts = lock(&self.layouts);
        if let Some(layout) = layouts.get(&key) {
            return Ok(layout.clone());
        }
        let layout = make()?;
        layouts.insert(key, layout.clone());
        Ok(layout)
    }

    /// The compute pipeline `key` names, made by `make` the first time.
    pub fn compute(
        &self,
        key: ComputeKey,
        make: impl FnOnce() -> Result<Pipeline>,
    ) -> Result<Pipeline> {
        let mut pipelines = lock(&self.compute);
        if let Some(pipeline) = pipelines.get(&key) {
            return Ok(pipeline.clone());
        }
        let pipeline = make()?;
        self.compute_made.fetch_add(1, Ordering::Relaxed);
        pipelines.insert(key, pipeline.clone());
        Ok(pipeline)
    }

    /// How many compute pipelines have been made (tests of the sharing).
    pub fn compute_made(&self) -> usize {
        self.compute_made.load(Ordering::Relaxed)
    }

    /// Drops every kept object: before the device's teardown counts the
    /// objects still alive.
    pub fn clear(&self) {
        lock(&self.compute).clear();
        lock(&self.layouts).clear();
    }
}
