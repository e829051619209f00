//! Objects made once per device and shared: the `Gpu` keeps its pipeline
//! layouts (found by what they declare, `descriptors::LayoutKey`) and
//! compute pipelines (by layout, SPIR-V and specialisation constants,
//! `pipeline::ComputeKey`) here, so that a pass made again on the same GPU
//! (bench's rows and its solvers side by side, the GPU report's parts)
//! takes the ones already made instead of compiling its kernels again. On
//! lavapipe compiling is most of a short run: a wind pass's kernels take
//! about 0.25 s of CPU (its V-cycle's tail kernel 60 ms) even with Mesa's
//! disk cache, and bench made them four times.
//!
//! Both are immutable once made, so sharing one is sharing its handle.
//! `Gpu::destroy` clears them before it counts what is still alive.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::Result;

/// Values by key, each made the first time it is asked for.
pub(super) struct MadeOnce<K, V> {
    made: Mutex<HashMap<K, V>>,
    /// How many values `make` has made.
    count: AtomicUsize,
}

impl<K, V> Default for MadeOnce<K, V> {
    fn default() -> Self {
        Self {
            made: Mutex::new(HashMap::new()),
            count: AtomicUsize::new(0),
        }
    }
}

impl<K: Hash + Eq, V: Clone> MadeOnce<K, V> {
    /// The map, whether or not a thread panicked holding it: an entry is
    /// whole or absent (inserted after it is made).
    fn lock(&self) -> MutexGuard<'_, HashMap<K, V>> {
        self.made.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The value of `key`, made by `make` the first time.
    pub fn get(&self, key: K, make: impl FnOnce() -> Result<V>) -> Result<V> {
        let mut made = self.lock();
        if let Some(value) = made.get(&key) {
            return Ok(value.clone());
        }
        let value = make()?;
        self.count.fetch_add(1, Ordering::Relaxed);
        made.insert(key, value.clone());
        Ok(value)
    }

    /// How many values have been made (tests of the sharing).
    pub fn count(&self) -> usize {
        self.count.load(Ordering::Relaxed)
    }

    /// Drops every kept value: before the device's teardown counts the
    /// objects still alive.
    pub fn clear(&self) {
        self.lock().clear();
    }
}
